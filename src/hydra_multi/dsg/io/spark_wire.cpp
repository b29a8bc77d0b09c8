#include "hydra_multi/dsg/io/spark_wire.h"

namespace hydra_multi::io::spark {

std::string tagName(uint8_t tag) {
  switch (tag) {
    case kNil:
      return "NIL (c0)";
    case kFalse:
      return "false (c2)";
    case kTrue:
      return "true (c3)";
    case kF32:
      return "FLOAT32 (ca)";
    case kF64:
      return "FLOAT64 (cb)";
    case kU8:
      return "UINT8 (cc)";
    case kU32:
      return "UINT32 (ce)";
    case kU64:
      return "UINT64 (cf)";
    case kI32:
      return "INT32 (d2)";
    case kI64:
      return "INT64 (d3)";
    case kArr32:
      return "ARR32 (dd)";
    case kStr32:
      return "STR32 (db)";
    default: {
      char text[16];
      std::snprintf(text, sizeof(text), "byte %02x", tag);
      return text;
    }
  }
}

void readMatrix(Reader& r, Matrix& m, uint8_t element_tag, const char* what) {
  const size_t at = r.offset();
  const uint32_t n = r.length(what);
  m.rows = r.i64(what);
  m.cols = r.i64(what);
  m.tag = element_tag;
  if (m.rows < 0 || m.cols < 0 || uint64_t(m.rows) * uint64_t(m.cols) + 2 != n)
    Reader::fail(at, what,
                 "a " + std::to_string(m.rows) + "x" + std::to_string(m.cols) +
                     " matrix in an array of " + std::to_string(n));
  const uint64_t size = uint64_t(m.rows) * uint64_t(m.cols);
  if (size * 2 > r.remaining())
    Reader::fail(at, what, std::to_string(size) + " elements run past the buffer");
  m.values.resize(size);
  for (double& v : m.values) {
    switch (element_tag) {
      case kF32:
        v = r.f32(what);
        break;
      case kF64:
        v = r.f64(what);
        break;
      default:
        v = r.u32(what);
        break;
    }
  }
}

void writeMatrix(Writer& w, const Matrix& m) {
  w.length(m.values.size() + 2);
  w.i64(m.rows);
  w.i64(m.cols);
  for (const double v : m.values) {
    switch (m.tag) {
      case kF32:
        w.f32(static_cast<float>(v));
        break;
      case kF64:
        w.f64(v);
        break;
      default:
        w.u32(static_cast<uint32_t>(v));
        break;
    }
  }
}

void readVector3(Reader& r, std::array<double, 3>& v, const char* what) {
  for (double& x : v) x = r.f64(what);
}

void writeVector3(Writer& w, const std::array<double, 3>& v) {
  for (const double x : v) w.f64(x);
}

void readVector3f(Reader& r, std::array<float, 3>& v, const char* what) {
  for (float& x : v) x = r.f32(what);
}

void writeVector3f(Writer& w, const std::array<float, 3>& v) {
  for (const float x : v) w.f32(x);
}

void readQuaternion(Reader& r, Quaternion& q, const char* what) {
  r.fixed(4, what);
  for (double& x : q) x = r.f64(what);
}

void writeQuaternion(Writer& w, const Quaternion& q) {
  w.length(4);
  for (const double x : q) w.f64(x);
}

void readColor(Reader& r, std::array<uint8_t, 4>& c, Version v) {
  const bool rgb = v <= Version{1, 0, 3};
  for (size_t i = 0; i < (rgb ? 3u : 4u); ++i) c[i] = r.u8("color");
  if (rgb) c[3] = 255;
}

void writeColor(Writer& w, const std::array<uint8_t, 4>& c, Version v) {
  const bool rgb = v <= Version{1, 0, 3};
  for (size_t i = 0; i < (rgb ? 3u : 4u); ++i) w.u8(c[i]);
}

void readBox(Reader& r, BoundingBox& b, Version v) {
  const bool min_max = v < Version{1, 0, 3};
  r.fixed(min_max ? 5 : 4, "bounding_box");
  b.type = r.i32("bounding_box type");
  if (b.type < 0 || b.type > 3)
    Reader::fail(r.offset(), "bounding_box type", std::to_string(b.type) + " is not 0-3");
  if (min_max) {
    std::array<std::array<float, 3>, 2> m;
    readVector3f(r, m[0], "bounding_box min");
    readVector3f(r, m[1], "bounding_box max");
    for (size_t i = 0; i < 3; ++i) b.dimensions[i] = m[1][i] - m[0][i];
    b.min_max = m;
  } else {
    readVector3f(r, b.dimensions, "bounding_box dimensions");
  }
  readVector3f(r, b.center, "bounding_box world_P_center");
  readMatrix(r, b.rotation, kF32, "bounding_box world_R_center");
  if (b.rotation.rows != 3 || b.rotation.cols != 3)
    Reader::fail(r.offset(), "bounding_box world_R_center", "not 3x3");
}

void writeBox(Writer& w, const BoundingBox& b, Version v) {
  const bool min_max = v < Version{1, 0, 3};
  w.length(min_max ? 5 : 4);
  w.i32(b.type);
  if (min_max) {
    // As read, or about the centre.
    std::array<std::array<float, 3>, 2> m;
    if (b.min_max) {
      m = *b.min_max;
    } else {
      for (size_t i = 0; i < 3; ++i) {
        m[0][i] = b.center[i] - 0.5f * b.dimensions[i];
        m[1][i] = b.center[i] + 0.5f * b.dimensions[i];
      }
    }
    writeVector3f(w, m[0]);
    writeVector3f(w, m[1]);
  } else {
    writeVector3f(w, b.dimensions);
  }
  writeVector3f(w, b.center);
  writeMatrix(w, b.rotation);
}

void readU64s(Reader& r, std::vector<uint64_t>& out, const char* what) {
  readVector(r, out, what, 9, [&](uint64_t& x) { x = r.u64(what); });
}

void writeU64s(Writer& w, const std::vector<uint64_t>& in) {
  writeVector(w, in, [&](uint64_t x) { w.u64(x); });
}

void readNearest(Reader& r, NearestVertex& v) {
  const char* what = "voxblox_mesh_connections";
  r.fixed(4, what);
  r.fixed(3, what);
  for (int32_t& x : v.block) x = r.i32(what);
  r.fixed(3, what);
  for (double& x : v.voxel) x = r.f64(what);
  v.vertex = r.u64(what);
  if (r.peek(kNil)) {
    r.skip(what);
    v.label.reset();
  } else {
    v.label = r.u32(what);
  }
}

void writeNearest(Writer& w, const NearestVertex& v) {
  w.length(4);
  w.length(3);
  for (const int32_t x : v.block) w.i32(x);
  w.length(3);
  for (const double x : v.voxel) w.f64(x);
  w.u64(v.vertex);
  if (v.label)
    w.u32(*v.label);
  else
    w.tag(kNil);
}

void readLayerKey(Reader& r, LayerKey& k, const char* what) {
  r.fixed(2, what);
  k.layer = r.i64(what);
  k.partition = r.u32(what);
}

void writeLayerKey(Writer& w, const LayerKey& k) {
  w.length(2);
  w.i64(k.layer);
  w.u32(k.partition);
}

}  // namespace hydra_multi::io::spark
