#pragma once
// Little-endian byte encoding for the binary format: fixed-size integers and IEEE floats, LEB128
// varints, zigzag-coded signed varints, length-prefixed strings, and the CRC-32 that guards each
// record. ByteReader checks every read against the end of the buffer and throws DecodeError with
// the byte offset; it never reads past the end.

#include <cstdint>
#include <string>
#include <string_view>

namespace hydra_multi::io {

/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), as zlib and PNG compute it.
uint32_t crc32(std::string_view bytes);

class ByteWriter {
 public:
  void u8(uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  void u16(uint16_t v) { fixed(v, 2); }
  void u32(uint32_t v) { fixed(v, 4); }
  void u64(uint64_t v) { fixed(v, 8); }
  void f32(float v);
  void f64(double v);
  void varint(uint64_t v);
  /// Zigzag: small magnitudes of either sign take few bytes.
  void svarint(int64_t v);
  void string(const std::string& s);
  void raw(std::string_view bytes) { bytes_.append(bytes); }

  const std::string& bytes() const { return bytes_; }
  std::string release() { return std::move(bytes_); }

 private:
  void fixed(uint64_t v, int n);
  std::string bytes_;
};

class ByteReader {
 public:
  /// Reads bytes[begin, end); offsets in messages count from `base` (the record's place in a file).
  ByteReader(std::string_view bytes, size_t base = 0) : bytes_(bytes), base_(base) {}

  uint8_t u8(const char* what);
  uint16_t u16(const char* what) { return static_cast<uint16_t>(fixed(2, what)); }
  uint32_t u32(const char* what) { return static_cast<uint32_t>(fixed(4, what)); }
  uint64_t u64(const char* what) { return fixed(8, what); }
  float f32(const char* what);
  double f64(const char* what);
  uint64_t varint(const char* what);
  int64_t svarint(const char* what);
  std::string string(const char* what, size_t max_size);
  std::string_view raw(size_t n, const char* what);
  /// A varint element count, rejected when `count * min_item_bytes` exceeds what is left, so that a
  /// corrupt count can never make the decoder allocate more than the input could hold.
  size_t count(const char* what, size_t min_item_bytes);

  size_t offset() const { return base_ + pos_; }
  size_t remaining() const { return bytes_.size() - pos_; }
  bool atEnd() const { return pos_ == bytes_.size(); }
  /// Throws DecodeError "byte <offset>: <message>".
  [[noreturn]] void fail(const std::string& message) const;

 private:
  uint64_t fixed(int n, const char* what);
  void need(size_t n, const char* what) const;
  std::string_view bytes_;
  size_t base_ = 0;
  size_t pos_ = 0;
};

}  // namespace hydra_multi::io
