#pragma once
// Spark-DSG's tagged binary values (../shared/reference/spark-dsg-wire.md §1.1-1.2), shared by the
// graph codec (spark_binary.cpp) and the attribute codec (spark_attributes.cpp): a Reader that
// checks every tag and names the field of every error with its byte offset, a Writer, and the
// composite values (Eigen matrices, vectors, quaternions, colours, boxes, layer keys), with the
// version gates of those that changed. Internal to dsg/io.

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/decode_error.h"
#include "hydra_multi/dsg/io/spark_binary.h"

namespace hydra_multi::io::spark {

// Tags (spark-dsg-wire.md §1.1).
inline constexpr uint8_t kNil = 0xc0, kFalse = 0xc2, kTrue = 0xc3, kF32 = 0xca, kF64 = 0xcb,
                         kU8 = 0xcc, kU32 = 0xce, kU64 = 0xcf, kI32 = 0xd2, kI64 = 0xd3,
                         kArr32 = 0xdd, kStr32 = 0xdb, kDynamicBegin = 0x00, kDynamicEnd = 0x01;

std::string tagName(uint8_t tag);

// The tagged layer over ByteReader: every read checks its tag and names its field.
class Reader {
 public:
  explicit Reader(std::string_view bytes, size_t base = 0)
      : bytes_(bytes), base_(base), r_(bytes, base) {}

  void expect(uint8_t tag, const char* what) {
    const size_t at = r_.offset();
    const uint8_t got = r_.u8(what);
    if (got != tag) fail(at, what, "expected " + tagName(tag) + ", found " + tagName(got));
  }
  bool boolean(const char* what) {
    const size_t at = r_.offset();
    const uint8_t got = r_.u8(what);
    if (got == kTrue) return true;
    if (got != kFalse) fail(at, what, "expected a bool (c2 or c3), found " + tagName(got));
    return false;
  }
  uint8_t u8(const char* what) { return expect(kU8, what), r_.u8(what); }
  uint32_t u32(const char* what) { return expect(kU32, what), r_.u32(what); }
  uint64_t u64(const char* what) { return expect(kU64, what), r_.u64(what); }
  int32_t i32(const char* what) { return expect(kI32, what), static_cast<int32_t>(r_.u32(what)); }
  int64_t i64(const char* what) { return expect(kI64, what), static_cast<int64_t>(r_.u64(what)); }
  float f32(const char* what) {
    return finite(kF32, what, [&] { return r_.f32(what); });
  }
  double f64(const char* what) {
    return finite(kF64, what, [&] { return r_.f64(what); });
  }
  // An array's or string's length (ARR32, or STR32 which Spark-DSG reads but never writes).
  uint32_t length(const char* what) {
    const size_t at = r_.offset();
    const uint8_t got = r_.u8(what);
    if (got != kArr32 && got != kStr32)
      fail(at, what, "expected an array length (dd), found " + tagName(got));
    return r_.u32(what);
  }
  // A count of items each at least `min_bytes` long, checked against what is left.
  size_t count(const char* what, size_t min_bytes) {
    const size_t at = r_.offset();
    const uint32_t n = length(what);
    if (uint64_t(n) * min_bytes > r_.remaining())
      fail(at, what,
           std::to_string(n) + " items need at least " + std::to_string(uint64_t(n) * min_bytes) +
               " bytes, " + std::to_string(r_.remaining()) + " are left");
    return n;
  }
  // A fixed array of exactly n items (Spark-DSG does not check this; we do).
  void fixed(uint32_t n, const char* what) {
    const size_t at = r_.offset();
    const uint32_t got = length(what);
    if (got != n)
      fail(at, what, "an array of " + std::to_string(n) + ", not " + std::to_string(got));
  }
  std::string string(const char* what) {
    const size_t n = count(what, 1);
    return std::string(r_.raw(n, what));
  }
  bool peek(uint8_t tag) const { return !r_.atEnd() && peekByte() == tag; }
  uint8_t peekByte() const { return static_cast<uint8_t>(bytes_[r_.offset() - base_]); }
  void skip(const char* what) { r_.u8(what); }
  bool atEnd() const { return r_.atEnd(); }
  size_t offset() const { return r_.offset(); }
  size_t remaining() const { return r_.remaining(); }

  [[noreturn]] static void fail(size_t at, const std::string& what, const std::string& why) {
    throw DecodeError("byte " + std::to_string(at) + ": " + what + ": " + why);
  }

 private:
  // A tagged float, refused unless finite.
  template <typename Read>
  auto finite(uint8_t tag, const char* what, Read read) -> decltype(read()) {
    expect(tag, what);
    const size_t at = r_.offset();
    const auto v = read();
    if (!std::isfinite(v)) fail(at, what, "not a finite number");
    return v;
  }

  std::string_view bytes_;
  size_t base_;
  ByteReader r_;
};

// The tagged writer.
class Writer {
 public:
  void tag(uint8_t t) { w_.u8(t); }
  void boolean(bool v) { tag(v ? kTrue : kFalse); }
  void u8(uint8_t v) { tag(kU8), w_.u8(v); }
  void u32(uint32_t v) { tag(kU32), w_.u32(v); }
  void u64(uint64_t v) { tag(kU64), w_.u64(v); }
  void i32(int32_t v) { tag(kI32), w_.u32(static_cast<uint32_t>(v)); }
  void i64(int64_t v) { tag(kI64), w_.u64(static_cast<uint64_t>(v)); }
  void f32(float v) { tag(kF32), w_.f32(v); }
  void f64(double v) { tag(kF64), w_.f64(v); }
  void length(size_t n) { tag(kArr32), w_.u32(static_cast<uint32_t>(n)); }
  void string(const std::string& s) {
    length(s.size());
    w_.raw(s);
  }
  std::string release() { return w_.release(); }

 private:
  ByteWriter w_;
};

// --- composite values (§1.2) ---

void readMatrix(Reader& r, Matrix& m, uint8_t element_tag, const char* what);
void writeMatrix(Writer& w, const Matrix& m);

void readVector3(Reader& r, std::array<double, 3>& v, const char* what);
void writeVector3(Writer& w, const std::array<double, 3>& v);
void readVector3f(Reader& r, std::array<float, 3>& v, const char* what);
void writeVector3f(Writer& w, const std::array<float, 3>& v);
void readQuaternion(Reader& r, Quaternion& q, const char* what);
void writeQuaternion(Writer& w, const Quaternion& q);
// Colour: r, g, b, a; up to 1.0.3 r, g, b (alpha 255).
void readColor(Reader& r, std::array<uint8_t, 4>& c, Version v);
void writeColor(Writer& w, const std::array<uint8_t, 4>& c, Version v);
// A box: type, dimensions, centre, rotation; before 1.0.3 type, min, max, centre, rotation.
void readBox(Reader& r, BoundingBox& b, Version v);
void writeBox(Writer& w, const BoundingBox& b, Version v);
template <typename T, typename Read>
void readVector(Reader& r, std::vector<T>& out, const char* what, size_t min_bytes, Read read) {
  out.resize(r.count(what, min_bytes));
  for (T& x : out) read(x);
}
template <typename T, typename Write>
void writeVector(Writer& w, const std::vector<T>& in, Write write) {
  w.length(in.size());
  for (const T& x : in) write(x);
}
void readU64s(Reader& r, std::vector<uint64_t>& out, const char* what);
void writeU64s(Writer& w, const std::vector<uint64_t>& in);
void readNearest(Reader& r, NearestVertex& v);
void writeNearest(Writer& w, const NearestVertex& v);
void readLayerKey(Reader& r, LayerKey& k, const char* what);
void writeLayerKey(Writer& w, const LayerKey& k);

}  // namespace hydra_multi::io::spark
