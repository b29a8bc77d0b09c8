// Writing the binary format's payloads (layout: binary_format.h).

#include "hydra_multi/dsg/io/binary_format.h"

#include <functional>

#include "hydra_multi/dsg/io/byte_codec.h"

namespace hydra_multi::io {
namespace {

// --- writing ---

void writeVector3d(ByteWriter& w, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) w.f64(v[i]);
}

void writeIndexList(ByteWriter& w, const std::vector<uint64_t>& indices) {
  w.varint(indices.size());
  int64_t previous = 0;
  for (const uint64_t index : indices) {
    w.svarint(static_cast<int64_t>(index) - previous);
    previous = static_cast<int64_t>(index);
  }
}

void writeSemantic(ByteWriter& w, const SemanticAttributes& s) {
  w.varint(s.label);
  w.string(s.name);
  w.u8(s.color.r);
  w.u8(s.color.g);
  w.u8(s.color.b);
  w.u8(s.bounding_box ? 1 : 0);
  if (s.bounding_box) {
    writeVector3d(w, s.bounding_box->min);
    writeVector3d(w, s.bounding_box->max);
  }
}

void writeNode(ByteWriter& w, const Node& node) {
  w.u64(node.id.value());
  w.u8(static_cast<uint8_t>(node.layer()));
  writeVector3d(w, node.position);
  w.svarint(node.last_update_time_ns);
  w.u8(node.is_active ? 1 : 0);
  if (const auto* agent = node.find<AgentAttributes>()) {
    for (int i = 0; i < 4; ++i) w.f64(agent->orientation.coeffs()[i]);  // x y z w
    w.svarint(agent->timestamp_ns);
    w.varint(agent->keyframe_id);
    return;
  }
  writeSemantic(w, *node.semantic());
  if (const auto* object = node.find<ObjectAttributes>()) writeIndexList(w, object->mesh_vertices);
  if (const auto* place = node.find<PlaceAttributes>()) {
    w.f64(place->distance);
    writeIndexList(w, place->mesh_vertices);
  }
}

void writeMeshDelta(ByteWriter& w, const MeshDelta& mesh) {
  w.varint(mesh.vertex_start);
  w.varint(mesh.vertices.size());
  int64_t previous_time = 0;
  for (const MeshVertex& v : mesh.vertices) {
    for (int i = 0; i < 3; ++i) w.f32(v.position[i]);
    w.u8(v.color.r);
    w.u8(v.color.g);
    w.u8(v.color.b);
    w.varint(v.label == MeshVertex::kUnlabeled ? 0 : uint64_t{v.label} + 1);
    w.u8(v.robot.index());
    w.svarint(v.time_ns - previous_time);
    previous_time = v.time_ns;
  }
  w.varint(mesh.face_start);
  w.varint(mesh.faces.size());
  int64_t previous = 0;
  for (const MeshFace& face : mesh.faces) {
    for (const uint32_t v : face) {
      w.svarint(static_cast<int64_t>(v) - previous);
      previous = v;
    }
  }
}

// Where writeRobotUpdate's sections end in the payload, for robotUpdateBytes.
struct SectionEnds {
  size_t header = 0, nodes_edges = 0, mesh = 0, pose_graph = 0, deformation = 0;
};

void writeGraphDelta(ByteWriter& w, const GraphDelta& delta, SectionEnds* ends = nullptr) {
  w.varint(delta.nodes.size());
  for (const Node& node : delta.nodes) writeNode(w, node);
  w.varint(delta.removed_nodes.size());
  for (const NodeId id : delta.removed_nodes) w.u64(id.value());
  w.varint(delta.edges.size());
  for (const Edge& edge : delta.edges) {
    w.u64(edge.source.value());
    w.u64(edge.target.value());
    w.f64(edge.info.weight);
    w.u8(edge.info.weighted ? 1 : 0);
  }
  w.varint(delta.removed_edges.size());
  for (const EdgeKey& key : delta.removed_edges) {
    w.u64(key.first().value());
    w.u64(key.second().value());
  }
  if (ends) ends->nodes_edges = w.bytes().size();
  writeMeshDelta(w, delta.mesh);
  if (ends) ends->mesh = w.bytes().size();
}

void writeRobotUpdate(ByteWriter& w, const RobotUpdate& u, SectionEnds* ends = nullptr) {
  w.u8(u.robot.index());
  w.varint(u.sequence);
  w.svarint(u.time_ns);
  w.u8(u.is_snapshot ? 1 : 0);
  w.varint(u.provided_layers);
  if (ends) ends->header = w.bytes().size();
  writeGraphDelta(w, u.graph, ends);
  w.varint(u.pose_graph.size());
  for (const PoseGraphEdge& e : u.pose_graph) {
    w.u64(e.from.value());
    w.u64(e.to.value());
    w.u8(static_cast<uint8_t>(e.kind));
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) w.f64(e.T_from_to.matrix()(r, c));
    }
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) w.f64(e.information(r, c));
    }
  }
  if (ends) ends->pose_graph = w.bytes().size();
  w.varint(u.deformation.points.size());
  for (const ControlPoint& p : u.deformation.points) {
    w.varint(p.id);
    writeVector3d(w, p.position);
    w.svarint(p.time_ns);
    w.u64(p.keyframe.value());
  }
  w.varint(u.deformation.edges.size());
  for (const ControlPointEdge& e : u.deformation.edges) {
    w.varint(e.from);
    w.varint(e.to);
  }
  if (ends) ends->deformation = w.bytes().size();
  w.varint(u.descriptors.size());
  for (const KeyframeDescriptor& d : u.descriptors) {
    w.u64(d.keyframe.value());
    w.varint(d.bow.size());
    for (const BowEntry& b : d.bow) {
      w.varint(b.word);
      w.f32(b.weight);
    }
    w.varint(d.keypoints.size());
    for (const Keypoint& k : d.keypoints) {
      for (int i = 0; i < 3; ++i) w.f32(k.position[i]);
      w.varint(k.word);
    }
  }
}

}  // namespace

std::string encodeSceneGraphBinary(const SceneGraph& graph) {
  ByteWriter payload;
  writeGraphDelta(payload, snapshotOf(graph));
  return encodeRecord(RecordKind::kSceneGraph, payload.bytes());
}

std::string encodeGraphDeltaBinary(const GraphDelta& delta) {
  ByteWriter payload;
  writeGraphDelta(payload, delta);
  return encodeRecord(RecordKind::kGraphDelta, payload.bytes());
}

std::string encodeRobotUpdateBinary(const RobotUpdate& update) {
  ByteWriter payload;
  writeRobotUpdate(payload, update);
  return encodeRecord(RecordKind::kRobotUpdate, payload.bytes());
}

RobotUpdateBytes robotUpdateBytes(const RobotUpdate& update) {
  ByteWriter payload;
  SectionEnds ends;
  writeRobotUpdate(payload, update, &ends);
  const size_t size = payload.bytes().size();
  RobotUpdateBytes bytes;
  bytes.header = recordSize(size) - size + ends.header;
  bytes.nodes_edges = ends.nodes_edges - ends.header;
  bytes.mesh = ends.mesh - ends.nodes_edges;
  bytes.pose_graph = ends.pose_graph - ends.mesh;
  bytes.deformation = ends.deformation - ends.pose_graph;
  bytes.descriptors = size - ends.deformation;
  return bytes;
}

size_t robotUpdateDigest(const RobotUpdate& update) {
  return std::hash<std::string>{}(encodeRobotUpdateBinary(update));
}

}  // namespace hydra_multi::io
