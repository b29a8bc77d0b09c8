#pragma once
// How a fuzz target cuts its input into what it decodes (fuzz/README.md):
//   frames   a count byte (mod 6), then per frame a 16-bit little-endian length and its bytes;
//            the last frame takes what is left
//   messages a sequence of frame groups, each as above, until the input ends
// Every cut is total: any input gives some frames, so the fuzzer never wastes an input. A record
// a robot could send can carry any checksum it likes, so targets that reach the frontend also
// decode records whose checksum withChecksum() made right.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hydra_multi/dsg/io/byte_codec.h"

namespace hydra_multi::fuzz {

/// Reads one group of frames from the front of `in` and moves `in` past it.
inline std::vector<std::string> takeFrames(std::string_view& in) {
  std::vector<std::string> frames;
  if (in.empty()) return frames;
  const size_t count = static_cast<uint8_t>(in[0]) % 6;
  in.remove_prefix(1);
  for (size_t k = 0; k < count; ++k) {
    if (k + 1 == count || in.size() < 2) {
      frames.emplace_back(in);
      in = {};
      break;
    }
    const size_t length = static_cast<uint8_t>(in[0]) | (static_cast<size_t>(in[1]) << 8 & 0xff00);
    in.remove_prefix(2);
    const size_t take = length < in.size() ? length : in.size();
    frames.emplace_back(in.substr(0, take));
    in.remove_prefix(take);
  }
  return frames;
}

/// The frames of one message, in the form takeFrames reads (for seeds).
inline std::string frameInput(const std::vector<std::string>& frames, bool last) {
  std::string out(1, static_cast<char>(frames.size()));
  for (size_t k = 0; k < frames.size(); ++k) {
    if (k + 1 == frames.size() && last) {
      out += frames[k];
      break;
    }
    const size_t n = frames[k].size() < 0xffff ? frames[k].size() : 0xffff;
    out += static_cast<char>(n & 0xff);
    out += static_cast<char>(n >> 8);
    out += frames[k].substr(0, n);
  }
  return out;
}

/// A .dsgb record ("HMDG", kind, version, size, payload, CRC-32 of kind to payload, little
/// endian) with its checksum recomputed; anything else as it is.
inline std::string withChecksum(std::string record) {
  if (record.size() < 9 || record.compare(0, 4, "HMDG") != 0) return record;
  const uint32_t crc = io::crc32(std::string_view(record).substr(4, record.size() - 8));
  for (int k = 0; k < 4; ++k) record[record.size() - 4 + k] = static_cast<char>(crc >> (8 * k));
  return record;
}

}  // namespace hydra_multi::fuzz
