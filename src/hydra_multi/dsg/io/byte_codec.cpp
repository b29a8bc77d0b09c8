#include "hydra_multi/dsg/io/byte_codec.h"

#include <array>
#include <cstring>

#include "hydra_multi/dsg/io/decode_error.h"

namespace hydra_multi::io {
namespace {

std::array<uint32_t, 256> makeCrcTable() {
  std::array<uint32_t, 256> table{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

}  // namespace

uint32_t crc32(std::string_view bytes) {
  static const std::array<uint32_t, 256> kTable = makeCrcTable();
  uint32_t c = 0xFFFFFFFFu;
  for (const char byte : bytes) c = kTable[(c ^ static_cast<uint8_t>(byte)) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void ByteWriter::fixed(uint64_t v, int n) {
  for (int i = 0; i < n; ++i) bytes_.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

void ByteWriter::f32(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  u32(bits);
}

void ByteWriter::f64(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  u64(bits);
}

void ByteWriter::varint(uint64_t v) {
  while (v >= 0x80u) {
    bytes_.push_back(static_cast<char>((v & 0x7Fu) | 0x80u));
    v >>= 7;
  }
  bytes_.push_back(static_cast<char>(v));
}

void ByteWriter::svarint(int64_t v) {
  varint((static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63));
}

void ByteWriter::string(const std::string& s) {
  varint(s.size());
  bytes_.append(s);
}

void ByteReader::fail(const std::string& message) const {
  throw DecodeError("byte " + std::to_string(offset()) + ": " + message);
}

void ByteReader::need(size_t n, const char* what) const {
  if (remaining() < n) {
    fail(std::string("truncated while reading ") + what + " (" + std::to_string(n) +
         " bytes needed, " + std::to_string(remaining()) + " left)");
  }
}

uint8_t ByteReader::u8(const char* what) {
  need(1, what);
  return static_cast<uint8_t>(bytes_[pos_++]);
}

uint64_t ByteReader::fixed(int n, const char* what) {
  need(static_cast<size_t>(n), what);
  uint64_t v = 0;
  for (int i = 0; i < n; ++i)
    v |= static_cast<uint64_t>(static_cast<uint8_t>(bytes_[pos_ + i])) << (8 * i);
  pos_ += static_cast<size_t>(n);
  return v;
}

float ByteReader::f32(const char* what) {
  const uint32_t bits = u32(what);
  float v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

double ByteReader::f64(const char* what) {
  const uint64_t bits = u64(what);
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

uint64_t ByteReader::varint(const char* what) {
  uint64_t v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    const uint8_t byte = u8(what);
    if (shift == 63 && byte > 1) fail(std::string("varint overflow in ") + what);
    v |= static_cast<uint64_t>(byte & 0x7Fu) << shift;
    if ((byte & 0x80u) == 0) return v;
  }
  fail(std::string("varint longer than 10 bytes in ") + what);
}

int64_t ByteReader::svarint(const char* what) {
  const uint64_t z = varint(what);
  return static_cast<int64_t>((z >> 1) ^ (~(z & 1u) + 1u));
}

std::string ByteReader::string(const char* what, size_t max_size) {
  const uint64_t size = varint(what);
  if (size > max_size) {
    fail(std::string(what) + " is " + std::to_string(size) + " bytes long (at most " +
         std::to_string(max_size) + ")");
  }
  return std::string(raw(static_cast<size_t>(size), what));
}

std::string_view ByteReader::raw(size_t n, const char* what) {
  need(n, what);
  const std::string_view view = bytes_.substr(pos_, n);
  pos_ += n;
  return view;
}

size_t ByteReader::count(const char* what, size_t min_item_bytes) {
  const uint64_t n = varint(what);
  if (min_item_bytes > 0 && n > remaining() / min_item_bytes) {
    fail(std::string(what) + " " + std::to_string(n) + " cannot fit in the " +
         std::to_string(remaining()) + " bytes left");
  }
  return static_cast<size_t>(n);
}

}  // namespace hydra_multi::io
