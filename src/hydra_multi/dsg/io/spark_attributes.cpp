#include "hydra_multi/dsg/io/spark_attributes.h"

#include <stdexcept>

namespace hydra_multi::io::spark {
namespace {

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

// Semantic features: double precision up to 1.0.4, single after.
uint8_t featureTag(Version v) { return v <= Version{1, 0, 4} ? kF64 : kF32; }

// A 2D place's shape: boundary, ellipse centroid and matrices (in both layouts).
void readPlace2dShape(Reader& r, Attributes& a) {
  readVector(r, a.boundary, "boundary", 27,
             [&](std::array<double, 3>& p) { readVector3(r, p, "boundary"); });
  readVector3(r, a.ellipse_centroid, "ellipse_centroid");
  readMatrix(r, a.ellipse_matrix_compress, kF64, "ellipse_matrix_compress");
  readMatrix(r, a.ellipse_matrix_expand, kF64, "ellipse_matrix_expand");
}
void writePlace2dShape(Writer& w, const Attributes& a) {
  writeVector(w, a.boundary, [&](const std::array<double, 3>& p) { writeVector3(w, p); });
  writeVector3(w, a.ellipse_centroid);
  writeMatrix(w, a.ellipse_matrix_compress);
  writeMatrix(w, a.ellipse_matrix_expand);
}

// What places and (up to 1.1.3) 2D places hold of the mesh: nearest voxblox vertices, mesh
// vertices, their labels, deformation-graph vertices.
void readMeshLinks(Reader& r, Attributes& a) {
  readVector(r, a.voxblox_mesh_connections, "voxblox_mesh_connections", 40,
             [&](NearestVertex& n) { readNearest(r, n); });
  readU64s(r, a.pcl_mesh_connections, "pcl_mesh_connections");
  readVector(r, a.mesh_vertex_labels, "mesh_vertex_labels", 2,
             [&](uint8_t& x) { x = r.u8("mesh_vertex_labels"); });
  readU64s(r, a.deformation_connections, "deformation_connections");
}
void writeMeshLinks(Writer& w, const Attributes& a) {
  writeVector(w, a.voxblox_mesh_connections, [&](const NearestVertex& n) { writeNearest(w, n); });
  writeU64s(w, a.pcl_mesh_connections);
  writeVector(w, a.mesh_vertex_labels, [&](uint8_t x) { w.u8(x); });
  writeU64s(w, a.deformation_connections);
}

// A 2D place up to 1.1.3.
void readPlace2d113(Reader& r, Attributes& a) {
  readPlace2dShape(r, a);
  readU64s(r, a.pcl_boundary_connections, "pcl_boundary_connections");
  readMeshLinks(r, a);
  a.need_cleanup_splitting = r.boolean("need_cleanup_splitting");
  a.has_active_mesh_indices = r.boolean("has_active_mesh_indices");
}
void writePlace2d113(Writer& w, const Attributes& a) {
  writePlace2dShape(w, a);
  writeU64s(w, a.pcl_boundary_connections);
  writeMeshLinks(w, a);
  w.boolean(a.need_cleanup_splitting);
  w.boolean(a.has_active_mesh_indices);
}

void readFields(Reader& r, Attributes& a, Kind kind, Version v) {
  if (kind == Kind::kEdge) {
    a.weighted = r.boolean("weighted");
    a.weight = r.f64("weight");
    return;
  }
  readVector3(r, a.position, "position");
  a.last_update_time_ns = r.u64("last_update_time_ns");
  a.is_active = r.boolean("is_active");
  if (Version{1, 0, 4} <= v) a.is_predicted = r.boolean("is_predicted");
  if (isSemantic(kind)) {
    a.name = r.string("name");
    readColor(r, a.color, v);
    readBox(r, a.bounding_box, v);
    a.semantic_label = r.u32("semantic_label");
    readMatrix(r, a.semantic_feature, featureTag(v), "semantic_feature");
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
      readMeshLinks(r, a);
      a.real_place = r.boolean("real_place");
      if (v <= Version{1, 0, 3}) a.predicted_place = r.boolean("predicted_place");
      a.active_frontier = r.boolean("active_frontier");
      readVector3(r, a.frontier_scale, "frontier_scale");
      readQuaternion(r, a.orientation, "orientation");
      a.need_cleanup = r.boolean("need_cleanup");
      a.num_frontier_voxels = r.u64("num_frontier_voxels");
      if (Version{1, 1, 3} <= v) a.anti_frontier = r.boolean("anti_frontier");
      break;
    case Kind::kPlace2d:
      if (v < Version{1, 1, 4}) {
        readPlace2d113(r, a);
      } else {
        readU64s(r, a.pcl_mesh_connections, "mesh_connections");
        readU64s(r, a.pcl_boundary_connections, "boundary_connections");
        readPlace2dShape(r, a);
        a.min_mesh_index = r.u64("min_mesh_index");
        a.max_mesh_index = r.u64("max_mesh_index");
        a.need_finish_merge = r.boolean("need_finish_merge");
        a.has_active_mesh_indices = r.boolean("has_active_mesh_indices");
      }
      break;
    case Kind::kAgent:
      if (Version{1, 1, 0} <= v) a.timestamp_ns = r.i64("timestamp");
      readQuaternion(r, a.world_R_body, "world_R_body");
      a.external_key = r.u64("external_key");
      readMatrix(r, a.dbow_ids, kU32, "dbow_ids");
      readMatrix(r, a.dbow_values, kF32, "dbow_values");
      break;
    default:
      break;
  }
}

void writeFields(Writer& w, const Attributes& a, Kind kind, Version v) {
  if (kind == Kind::kEdge) {
    w.boolean(a.weighted);
    w.f64(a.weight);
    return;
  }
  writeVector3(w, a.position);
  w.u64(a.last_update_time_ns);
  w.boolean(a.is_active);
  if (Version{1, 0, 4} <= v) w.boolean(a.is_predicted);
  if (isSemantic(kind)) {
    w.string(a.name);
    writeColor(w, a.color, v);
    writeBox(w, a.bounding_box, v);
    w.u32(a.semantic_label);
    Matrix feature = a.semantic_feature;
    feature.tag = featureTag(v);
    writeMatrix(w, feature);
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
      writeMeshLinks(w, a);
      w.boolean(a.real_place);
      if (v <= Version{1, 0, 3}) w.boolean(a.predicted_place);
      w.boolean(a.active_frontier);
      writeVector3(w, a.frontier_scale);
      writeQuaternion(w, a.orientation);
      w.boolean(a.need_cleanup);
      w.u64(a.num_frontier_voxels);
      if (Version{1, 1, 3} <= v) w.boolean(a.anti_frontier);
      break;
    case Kind::kPlace2d:
      if (v < Version{1, 1, 4}) {
        writePlace2d113(w, a);
      } else {
        writeU64s(w, a.pcl_mesh_connections);
        writeU64s(w, a.pcl_boundary_connections);
        writePlace2dShape(w, a);
        w.u64(a.min_mesh_index);
        w.u64(a.max_mesh_index);
        w.boolean(a.need_finish_merge);
        w.boolean(a.has_active_mesh_indices);
      }
      break;
    case Kind::kAgent:
      if (Version{1, 1, 0} <= v) w.i64(a.timestamp_ns);
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
}  // namespace

void readAttributes(Reader& r, const std::vector<std::string>& types,
                    const std::vector<std::optional<Kind>>& kinds, Version v, uint8_t& type_id,
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
  if (Version{1, 0, 6} <= v) a.metadata = r.string("attribute metadata");
  readFields(r, a, *kinds[type_id], v);
}

std::vector<std::optional<Kind>> kindsOf(const std::vector<std::string>& names) {
  std::vector<std::optional<Kind>> kinds;
  for (const std::string& n : names) kinds.push_back(kindOf(n));
  return kinds;
}

void writeAttributes(Writer& w, const std::vector<std::string>& types, uint8_t type_id,
                     const Attributes& a, Version v) {
  const std::string& name = type_id < types.size() ? types[type_id] : a.type;
  const std::optional<Kind> kind = kindOf(name);
  if (!kind) throw std::invalid_argument("spark binary: attribute type '" + name + "' is unknown");
  w.u8(type_id);
  if (Version{1, 0, 6} <= v) w.string(a.metadata);
  writeFields(w, a, *kind, v);
}

}  // namespace hydra_multi::io::spark
