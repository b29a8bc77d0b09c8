#include "hydra_multi/dsg/io/spark_binary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/decode_error.h"

namespace hydra_multi::io::spark {
namespace {

// Tags (spark-dsg-wire.md §1.1).
constexpr uint8_t kNil = 0xc0, kFalse = 0xc2, kTrue = 0xc3, kF32 = 0xca, kF64 = 0xcb, kU8 = 0xcc,
                  kU32 = 0xce, kU64 = 0xcf, kI32 = 0xd2, kI64 = 0xd3, kArr32 = 0xdd, kStr32 = 0xdb,
                  kDynamicBegin = 0x00, kDynamicEnd = 0x01;

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
void readColor(Reader& r, std::array<uint8_t, 4>& c) {
  for (uint8_t& x : c) x = r.u8("color");
}
void writeColor(Writer& w, const std::array<uint8_t, 4>& c) {
  for (const uint8_t x : c) w.u8(x);
}
void readBox(Reader& r, BoundingBox& b) {
  r.fixed(4, "bounding_box");
  b.type = r.i32("bounding_box type");
  if (b.type < 0 || b.type > 3)
    Reader::fail(r.offset(), "bounding_box type", std::to_string(b.type) + " is not 0-3");
  readVector3f(r, b.dimensions, "bounding_box dimensions");
  readVector3f(r, b.center, "bounding_box world_P_center");
  readMatrix(r, b.rotation, kF32, "bounding_box world_R_center");
  if (b.rotation.rows != 3 || b.rotation.cols != 3)
    Reader::fail(r.offset(), "bounding_box world_R_center", "not 3x3");
}
void writeBox(Writer& w, const BoundingBox& b) {
  w.length(4);
  w.i32(b.type);
  writeVector3f(w, b.dimensions);
  writeVector3f(w, b.center);
  writeMatrix(w, b.rotation);
}
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

// --- attributes (§1.7): each type's fields after its base's ---

enum class Kind { kNode, kSemantic, kObject, kRoom, kPlace, kPlace2d, kAgent, kEdge };

std::optional<Kind> kindOf(const std::string& name) {
  static const std::vector<std::pair<std::string, Kind>> kinds = {
      {"NodeAttributes", Kind::kNode},         {"SemanticNodeAttributes", Kind::kSemantic},
      {"ObjectNodeAttributes", Kind::kObject}, {"RoomNodeAttributes", Kind::kRoom},
      {"PlaceNodeAttributes", Kind::kPlace},   {"Place2dNodeAttributes", Kind::kPlace2d},
      {"AgentNodeAttributes", Kind::kAgent},   {"EdgeAttributes", Kind::kEdge}};
  for (const auto& [n, k] : kinds) {
    if (n == name) return k;
  }
  return std::nullopt;
}

bool isSemantic(Kind k) {
  return k == Kind::kSemantic || k == Kind::kObject || k == Kind::kRoom || k == Kind::kPlace ||
         k == Kind::kPlace2d;
}

void readFields(Reader& r, Attributes& a, Kind kind) {
  if (kind == Kind::kEdge) {
    a.weighted = r.boolean("weighted");
    a.weight = r.f64("weight");
    return;
  }
  readVector3(r, a.position, "position");
  a.last_update_time_ns = r.u64("last_update_time_ns");
  a.is_active = r.boolean("is_active");
  a.is_predicted = r.boolean("is_predicted");
  if (isSemantic(kind)) {
    a.name = r.string("name");
    readColor(r, a.color);
    readBox(r, a.bounding_box);
    a.semantic_label = r.u32("semantic_label");
    readMatrix(r, a.semantic_feature, kF32, "semantic_feature");
  }
  switch (kind) {
    case Kind::kObject:
      readU64s(r, a.mesh_connections, "mesh_connections");
      a.registered = r.boolean("registered");
      readQuaternion(r, a.world_R_object, "world_R_object");
      break;
    case Kind::kRoom:
      readVector(r, a.semantic_class_probabilities, "semantic_class_probabilities", 14,
                 [&](std::pair<std::string, double>& p) {
                   p.first = r.string("semantic_class_probabilities");
                   p.second = r.f64("semantic_class_probabilities");
                 });
      break;
    case Kind::kPlace:
      a.distance = r.f64("distance");
      a.num_basis_points = r.u32("num_basis_points");
      readVector(r, a.voxblox_mesh_connections, "voxblox_mesh_connections", 40,
                 [&](NearestVertex& v) { readNearest(r, v); });
      readU64s(r, a.pcl_mesh_connections, "pcl_mesh_connections");
      readVector(r, a.mesh_vertex_labels, "mesh_vertex_labels", 2,
                 [&](uint8_t& x) { x = r.u8("mesh_vertex_labels"); });
      readU64s(r, a.deformation_connections, "deformation_connections");
      a.real_place = r.boolean("real_place");
      a.active_frontier = r.boolean("active_frontier");
      readVector3(r, a.frontier_scale, "frontier_scale");
      readQuaternion(r, a.orientation, "orientation");
      a.need_cleanup = r.boolean("need_cleanup");
      a.num_frontier_voxels = r.u64("num_frontier_voxels");
      a.anti_frontier = r.boolean("anti_frontier");
      break;
    case Kind::kPlace2d:
      readVector(r, a.boundary, "boundary", 27,
                 [&](std::array<double, 3>& p) { readVector3(r, p, "boundary"); });
      readVector3(r, a.ellipse_centroid, "ellipse_centroid");
      readMatrix(r, a.ellipse_matrix_compress, kF64, "ellipse_matrix_compress");
      readMatrix(r, a.ellipse_matrix_expand, kF64, "ellipse_matrix_expand");
      readU64s(r, a.pcl_boundary_connections, "pcl_boundary_connections");
      readVector(r, a.voxblox_mesh_connections, "voxblox_mesh_connections", 40,
                 [&](NearestVertex& v) { readNearest(r, v); });
      readU64s(r, a.pcl_mesh_connections, "pcl_mesh_connections");
      readVector(r, a.mesh_vertex_labels, "mesh_vertex_labels", 2,
                 [&](uint8_t& x) { x = r.u8("mesh_vertex_labels"); });
      readU64s(r, a.deformation_connections, "deformation_connections");
      a.need_cleanup_splitting = r.boolean("need_cleanup_splitting");
      a.has_active_mesh_indices = r.boolean("has_active_mesh_indices");
      break;
    case Kind::kAgent:
      a.timestamp_ns = r.i64("timestamp");
      readQuaternion(r, a.world_R_body, "world_R_body");
      a.external_key = r.u64("external_key");
      readMatrix(r, a.dbow_ids, kU32, "dbow_ids");
      readMatrix(r, a.dbow_values, kF32, "dbow_values");
      break;
    default:
      break;
  }
}

void writeFields(Writer& w, const Attributes& a, Kind kind) {
  if (kind == Kind::kEdge) {
    w.boolean(a.weighted);
    w.f64(a.weight);
    return;
  }
  writeVector3(w, a.position);
  w.u64(a.last_update_time_ns);
  w.boolean(a.is_active);
  w.boolean(a.is_predicted);
  if (isSemantic(kind)) {
    w.string(a.name);
    writeColor(w, a.color);
    writeBox(w, a.bounding_box);
    w.u32(a.semantic_label);
    writeMatrix(w, a.semantic_feature);
  }
  switch (kind) {
    case Kind::kObject:
      writeU64s(w, a.mesh_connections);
      w.boolean(a.registered);
      writeQuaternion(w, a.world_R_object);
      break;
    case Kind::kRoom:
      w.length(a.semantic_class_probabilities.size());
      for (const auto& [name, p] : a.semantic_class_probabilities) {
        w.string(name);
        w.f64(p);
      }
      break;
    case Kind::kPlace:
      w.f64(a.distance);
      w.u32(a.num_basis_points);
      writeVector(w, a.voxblox_mesh_connections,
                  [&](const NearestVertex& v) { writeNearest(w, v); });
      writeU64s(w, a.pcl_mesh_connections);
      writeVector(w, a.mesh_vertex_labels, [&](uint8_t x) { w.u8(x); });
      writeU64s(w, a.deformation_connections);
      w.boolean(a.real_place);
      w.boolean(a.active_frontier);
      writeVector3(w, a.frontier_scale);
      writeQuaternion(w, a.orientation);
      w.boolean(a.need_cleanup);
      w.u64(a.num_frontier_voxels);
      w.boolean(a.anti_frontier);
      break;
    case Kind::kPlace2d:
      writeVector(w, a.boundary, [&](const std::array<double, 3>& p) { writeVector3(w, p); });
      writeVector3(w, a.ellipse_centroid);
      writeMatrix(w, a.ellipse_matrix_compress);
      writeMatrix(w, a.ellipse_matrix_expand);
      writeU64s(w, a.pcl_boundary_connections);
      writeVector(w, a.voxblox_mesh_connections,
                  [&](const NearestVertex& v) { writeNearest(w, v); });
      writeU64s(w, a.pcl_mesh_connections);
      writeVector(w, a.mesh_vertex_labels, [&](uint8_t x) { w.u8(x); });
      writeU64s(w, a.deformation_connections);
      w.boolean(a.need_cleanup_splitting);
      w.boolean(a.has_active_mesh_indices);
      break;
    case Kind::kAgent:
      w.i64(a.timestamp_ns);
      writeQuaternion(w, a.world_R_body);
      w.u64(a.external_key);
      writeMatrix(w, a.dbow_ids);
      writeMatrix(w, a.dbow_values);
      break;
    default:
      break;
  }
}

// An attribute record: type id (into `types`), metadata, the fields.
void readAttributes(Reader& r, const std::vector<std::string>& types,
                    const std::vector<std::optional<Kind>>& kinds, uint8_t& type_id,
                    Attributes& a) {
  const size_t at = r.offset();
  type_id = r.u8("attribute type");
  if (type_id >= types.size())
    Reader::fail(at, "attribute type",
                 "id " + std::to_string(type_id) + " is not in the " +
                     std::to_string(types.size()) + " names of the message");
  if (!kinds[type_id])
    Reader::fail(at, "attribute type", "'" + types[type_id] + "' is not a type this codec reads");
  a.type = types[type_id];
  a.metadata = r.string("attribute metadata");
  readFields(r, a, *kinds[type_id]);
}

std::vector<std::optional<Kind>> kindsOf(const std::vector<std::string>& names) {
  std::vector<std::optional<Kind>> kinds;
  for (const std::string& n : names) kinds.push_back(kindOf(n));
  return kinds;
}

Kind writableKind(const std::vector<std::string>& types, uint8_t id, const Attributes& a) {
  const std::string& name = id < types.size() ? types[id] : a.type;
  const std::optional<Kind> kind = kindOf(name);
  if (!kind) throw std::invalid_argument("spark binary: attribute type '" + name + "' is unknown");
  return *kind;
}

void readMesh(Reader& r, Mesh& m) {
  m.has_colors = r.boolean("mesh has_colors");
  m.has_stamps = r.boolean("mesh has_timestamps");
  m.has_labels = r.boolean("mesh has_labels");
  m.has_first_seen = r.boolean("mesh has_first_seen_stamps");
  readVector(r, m.points, "mesh points", 15,
             [&](std::array<float, 3>& p) { readVector3f(r, p, "mesh points"); });
  readVector(r, m.colors, "mesh colors", 8, [&](std::array<uint8_t, 4>& c) {
    for (uint8_t& x : c) x = r.u8("mesh colors");
  });
  readU64s(r, m.stamps, "mesh stamps");
  readVector(r, m.labels, "mesh labels", 5, [&](uint32_t& x) { x = r.u32("mesh labels"); });
  readU64s(r, m.first_seen_stamps, "mesh first_seen_stamps");
  readVector(r, m.faces, "mesh faces", 32, [&](std::array<uint64_t, 3>& f) {
    r.fixed(3, "mesh faces");
    for (uint64_t& i : f) {
      const size_t at = r.offset();
      i = r.u64("mesh faces");
      if (i >= m.points.size())
        Reader::fail(at, "mesh faces",
                     "vertex " + std::to_string(i) + " of " + std::to_string(m.points.size()));
    }
  });
}

void writeMesh(Writer& w, const Mesh& m) {
  w.boolean(m.has_colors);
  w.boolean(m.has_stamps);
  w.boolean(m.has_labels);
  w.boolean(m.has_first_seen);
  writeVector(w, m.points, [&](const std::array<float, 3>& p) { writeVector3f(w, p); });
  writeVector(w, m.colors, [&](const std::array<uint8_t, 4>& c) { writeColor(w, c); });
  writeU64s(w, m.stamps);
  writeVector(w, m.labels, [&](uint32_t x) { w.u32(x); });
  writeU64s(w, m.first_seen_stamps);
  writeVector(w, m.faces, [&](const std::array<uint64_t, 3>& f) {
    w.length(3);
    for (const uint64_t i : f) w.u64(i);
  });
}

Graph readGraph(Reader& r) {
  Graph g;
  readVector(r, g.layer_keys, "layer keys", 20,
             [&](LayerKey& k) { readLayerKey(r, k, "layer keys"); });
  readVector(r, g.node_types, "node attribute names", 5,
             [&](std::string& s) { s = r.string("node attribute names"); });
  readVector(r, g.edge_types, "edge attribute names", 5,
             [&](std::string& s) { s = r.string("edge attribute names"); });
  readVector(r, g.layer_names, "layer names", 25, [&](std::pair<std::string, LayerKey>& p) {
    p.first = r.string("layer names");
    readLayerKey(r, p.second, "layer names");
  });
  g.metadata = r.string("graph metadata");
  const std::vector<std::optional<Kind>> node_kinds = kindsOf(g.node_types);
  const std::vector<std::optional<Kind>> edge_kinds = kindsOf(g.edge_types);
  r.expect(kDynamicBegin, "nodes");
  while (!r.peek(kDynamicEnd)) {
    const size_t at = r.offset();
    try {
      Node n;
      r.fixed(4, "node");
      n.layer = r.i64("node layer");
      n.id = r.u64("node id");
      n.partition = r.u32("node partition");
      readAttributes(r, g.node_types, node_kinds, n.type_id, n.attributes);
      g.nodes.push_back(std::move(n));
    } catch (const DecodeError& e) {
      throw e.within("node " + std::to_string(g.nodes.size()) + " (at byte " + std::to_string(at) +
                     ")");
    }
  }
  r.skip("nodes");
  r.expect(kDynamicBegin, "edges");
  while (!r.peek(kDynamicEnd)) {
    const size_t at = r.offset();
    try {
      Edge e;
      r.fixed(3, "edge");
      e.source = r.u64("edge source");
      e.target = r.u64("edge target");
      readAttributes(r, g.edge_types, edge_kinds, e.type_id, e.attributes);
      g.edges.push_back(std::move(e));
    } catch (const DecodeError& error) {
      throw error.within("edge " + std::to_string(g.edges.size()) + " (at byte " +
                         std::to_string(at) + ")");
    }
  }
  r.skip("edges");
  // A missing mesh flag at the end means no mesh, as Spark-DSG reads it.
  if (!r.atEnd() && r.boolean("mesh flag")) {
    g.mesh.emplace();
    readMesh(r, *g.mesh);
  }
  if (!r.atEnd())
    Reader::fail(r.offset(), "end", std::to_string(r.remaining()) + " bytes after the graph");
  return g;
}

// An attribute record: type id, metadata, the fields (readAttributes' inverse).
void writeAttributes(Writer& w, const std::vector<std::string>& types, uint8_t type_id,
                     const Attributes& a) {
  w.u8(type_id);
  w.string(a.metadata);
  writeFields(w, a, writableKind(types, type_id, a));
}

void writeGraph(Writer& w, const Graph& g) {
  writeVector(w, g.layer_keys, [&](const LayerKey& k) { writeLayerKey(w, k); });
  writeVector(w, g.node_types, [&](const std::string& s) { w.string(s); });
  writeVector(w, g.edge_types, [&](const std::string& s) { w.string(s); });
  writeVector(w, g.layer_names, [&](const std::pair<std::string, LayerKey>& p) {
    w.string(p.first);
    writeLayerKey(w, p.second);
  });
  w.string(g.metadata);
  w.tag(kDynamicBegin);
  for (const Node& n : g.nodes) {
    w.length(4);
    w.i64(n.layer);
    w.u64(n.id);
    w.u32(n.partition);
    writeAttributes(w, g.node_types, n.type_id, n.attributes);
  }
  w.tag(kDynamicEnd);
  w.tag(kDynamicBegin);
  for (const Edge& e : g.edges) {
    w.length(3);
    w.u64(e.source);
    w.u64(e.target);
    writeAttributes(w, g.edge_types, e.type_id, e.attributes);
  }
  w.tag(kDynamicEnd);
  w.boolean(g.mesh.has_value());
  if (g.mesh) writeMesh(w, *g.mesh);
}

Result<Graph> decodeGraph(std::string_view bytes, size_t base, Version version, const char* form) {
  if (!(version == kVersion))
    return Error{std::string("spark binary (") + form + "): version " + version.str() +
                 ": this build reads " + kVersion.str() + " only"};
  try {
    Reader r(bytes, base);
    return readGraph(r);
  } catch (const DecodeError& e) {
    return Error{std::string("spark binary (") + form + "): " + e.what()};
  }
}

}  // namespace

std::string Version::str() const {
  return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch);
}

const std::vector<std::string>& knownNodeTypes() {
  static const std::vector<std::string> types = {
      "NodeAttributes",      "SemanticNodeAttributes", "ObjectNodeAttributes", "RoomNodeAttributes",
      "PlaceNodeAttributes", "Place2dNodeAttributes",  "AgentNodeAttributes"};
  return types;
}

Result<Graph> decodeWire(std::string_view bytes, Version version) {
  return decodeGraph(bytes, 0, version, "wire");
}

Result<Graph> decodeFile(std::string_view bytes, FileHeader* header) {
  FileHeader h;
  size_t at = 0;
  try {
    Reader r(bytes);
    const std::string magic = r.string("file header");
    if (magic != "SPARK_DSG")
      Reader::fail(0, "file header", "'" + magic + "' is not SPARK_DSG: not a Spark-DSG file");
    h.project = r.string("file header project");
    h.version.major = r.u8("file header version");
    h.version.minor = r.u8("file header version");
    h.version.patch = r.u8("file header version");
    at = r.offset();
  } catch (const DecodeError& e) {
    return Error{std::string("spark binary (file): ") + e.what()};
  }
  if (h.project != "main")
    return Error{"spark binary (file): project '" + h.project +
                 "': Spark-DSG reads only 'main' files"};
  if (header != nullptr) *header = h;
  return decodeGraph(bytes.substr(at), at, h.version, "file");
}

std::string encodeWire(const Graph& graph) {
  Writer w;
  writeGraph(w, graph);
  return w.release();
}

std::string encodeFileHeader(const FileHeader& header) {
  Writer w;
  w.string("SPARK_DSG");
  w.string(header.project);
  w.u8(header.version.major);
  w.u8(header.version.minor);
  w.u8(header.version.patch);
  return w.release();
}

std::string encodeFile(const Graph& graph, const FileHeader& header) {
  return encodeFileHeader(header) + encodeWire(graph);
}

}  // namespace hydra_multi::io::spark
