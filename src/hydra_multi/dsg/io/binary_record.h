#pragma once
// Records of the binary format (.dsgb): a file is a sequence of them.
//
//   "HMDG" | kind u8 (1 graph, 2 robot update, 3 graph delta) | version u16 | payload size varint |
//   payload | CRC-32 u32 of everything from kind to the end of the payload
//
// The payloads' layout is binary_format.h's.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "hydra_multi/core/result.h"

namespace hydra_multi::io {

inline constexpr uint16_t kBinaryVersion = 1;

enum class RecordKind : uint8_t { kSceneGraph = 1, kRobotUpdate = 2, kGraphDelta = 3 };

/// One record of a file: its kind, its place and its payload.
struct RecordView {
  RecordKind kind;
  size_t offset = 0;  ///< where the record starts in the file
  std::string_view payload;
};

/// A whole record (magic, header, payload, checksum) around a payload.
std::string encodeRecord(RecordKind kind, const std::string& payload);
/// The size of the record encodeRecord makes of a payload of this size, without making it.
size_t recordSize(size_t payload_size);

/// Reads the records of a file one at a time, so a stream of updates is never loaded whole into
/// decoded form. next() returns nullopt at the end; a broken record is an error naming its offset
/// (checksum, version, kind, truncation), after which the reader is at the end unless
/// resynchronize() moves it on.
class RecordReader {
 public:
  explicit RecordReader(std::string_view bytes) : bytes_(bytes) {}
  /// The next record, nullopt at the end of the file, or an error.
  Result<std::optional<RecordView>> next();
  /// After an error of next(): moves to the next magic bytes past the broken record's start, so the
  /// records after a damaged one can still be read (each has its own checksum, so a stray "HMDG"
  /// inside a payload is caught as broken in turn). Returns the byte it moved to, or nullopt if
  /// there is none (the reader stays at the end).
  std::optional<size_t> resynchronize();

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
  std::optional<size_t> broken_;  // start of the record next() last refused
};

}  // namespace hydra_multi::io
