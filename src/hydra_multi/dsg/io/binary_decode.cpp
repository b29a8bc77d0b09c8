// Reading the binary format's payloads (layout: binary_format.h): every length is checked against
// the bytes left and every value before anything is returned.

#include "hydra_multi/dsg/io/binary_format.h"

#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/decode_error.h"

namespace hydra_multi::io {
namespace {

constexpr size_t kMaxString = 1 << 16;
// Smallest encodings, for bounding element counts by the bytes left (see ByteReader::count).
constexpr size_t kMinNodeBytes = 8 + 1 + 24 + 1 + 1;
constexpr size_t kMinEdgeBytes = 8 + 8 + 8 + 1;
constexpr size_t kMinVertexBytes = 12 + 3 + 1 + 1 + 1;
constexpr size_t kMinPoseEdgeBytes = 8 + 8 + 1 + 12 * 8 + 36 * 8;

// --- reading ---

Eigen::Vector3d readVector3d(ByteReader& r, const char* what) {
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = r.f64(what);
  return v;
}

uint32_t readU32Varint(ByteReader& r, const char* what) {
  const uint64_t v = r.varint(what);
  if (v > UINT32_MAX) r.fail(std::string(what) + " does not fit in 32 bits");
  return static_cast<uint32_t>(v);
}

bool readBool(ByteReader& r, const char* what) {
  const uint8_t v = r.u8(what);
  if (v > 1) r.fail(std::string(what) + " is " + std::to_string(v) + ", not 0 or 1");
  return v == 1;
}

// running += the next signed varint of a delta-coded list; refused when the sum leaves int64.
void addDelta(ByteReader& r, int64_t& running, const char* what) {
  if (__builtin_add_overflow(running, r.svarint(what), &running))
    r.fail(std::string(what) + " out of range (the running sum of its deltas overflows)");
}

std::vector<uint64_t> readIndexList(ByteReader& r) {
  const size_t n = r.count("mesh vertex count", 1);
  std::vector<uint64_t> indices(n);
  int64_t previous = 0;
  for (size_t i = 0; i < n; ++i) {
    addDelta(r, previous, "mesh vertex index");
    if (previous < 0) r.fail("negative mesh vertex index");
    indices[i] = static_cast<uint64_t>(previous);
  }
  return indices;
}

SemanticAttributes readSemantic(ByteReader& r) {
  SemanticAttributes s;
  s.label = readU32Varint(r, "semantic label");
  s.name = r.string("name", kMaxString);
  s.color.r = r.u8("color");
  s.color.g = r.u8("color");
  s.color.b = r.u8("color");
  if (readBool(r, "bounding box flag")) {
    BoundingBox box;
    box.min = readVector3d(r, "bounding box");
    box.max = readVector3d(r, "bounding box");
    s.bounding_box = box;
  }
  return s;
}

Node readNode(ByteReader& r) {
  const NodeId id(r.u64("node id"));
  const uint8_t layer = r.u8("layer");
  if (layer > static_cast<uint8_t>(Layer::kBuildings)) {
    r.fail("unknown layer " + std::to_string(layer) + " of node " + id.str());
  }
  Node node = makeNode(id, static_cast<Layer>(layer));
  node.position = readVector3d(r, "position");
  node.last_update_time_ns = r.svarint("last update time");
  node.is_active = readBool(r, "is_active");
  if (auto* agent = node.find<AgentAttributes>()) {
    for (int i = 0; i < 4; ++i) agent->orientation.coeffs()[i] = r.f64("orientation");
    agent->timestamp_ns = r.svarint("timestamp");
    agent->keyframe_id = r.varint("keyframe id");
    return node;
  }
  *node.semantic() = readSemantic(r);
  if (auto* object = node.find<ObjectAttributes>()) object->mesh_vertices = readIndexList(r);
  if (auto* place = node.find<PlaceAttributes>()) {
    place->distance = r.f64("place distance");
    place->mesh_vertices = readIndexList(r);
  }
  return node;
}

template <typename ReadItem>
auto readList(ByteReader& r, const char* name, size_t min_bytes, ReadItem read_item) {
  const size_t n = r.count((std::string(name) + " count").c_str(), min_bytes);
  std::vector<decltype(read_item(r))> items;
  items.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    try {
      items.push_back(read_item(r));
    } catch (const DecodeError& error) {
      throw error.within(std::string(name) + " " + std::to_string(i));
    }
  }
  return items;
}

MeshDelta readMeshDelta(ByteReader& r) {
  MeshDelta mesh;
  mesh.vertex_start = r.varint("mesh vertex start");
  int64_t time = 0;
  mesh.vertices = readList(r, "mesh vertex", kMinVertexBytes, [&time](ByteReader& in) {
    MeshVertex v;
    for (int i = 0; i < 3; ++i) v.position[i] = in.f32("vertex position");
    v.color.r = in.u8("vertex color");
    v.color.g = in.u8("vertex color");
    v.color.b = in.u8("vertex color");
    const uint64_t label = in.varint("vertex label");
    if (label > uint64_t{UINT32_MAX}) in.fail("vertex label does not fit in 32 bits");
    v.label = label == 0 ? MeshVertex::kUnlabeled : static_cast<uint32_t>(label - 1);
    v.robot = RobotId(in.u8("vertex robot"));
    addDelta(in, time, "vertex time");
    v.time_ns = time;
    return v;
  });
  mesh.face_start = r.varint("mesh face start");
  int64_t previous = 0;
  mesh.faces = readList(r, "mesh face", 3, [&previous](ByteReader& in) {
    MeshFace face;
    for (uint32_t& v : face) {
      addDelta(in, previous, "face vertex");
      if (previous < 0 || previous > int64_t{UINT32_MAX}) in.fail("face vertex index out of range");
      v = static_cast<uint32_t>(previous);
    }
    return face;
  });
  return mesh;
}

GraphDelta readGraphDelta(ByteReader& r) {
  GraphDelta delta;
  delta.nodes = readList(r, "node", kMinNodeBytes, readNode);
  delta.removed_nodes =
      readList(r, "removed node", 8, [](ByteReader& in) { return NodeId(in.u64("node id")); });
  delta.edges = readList(r, "edge", kMinEdgeBytes, [](ByteReader& in) {
    Edge edge;
    edge.source = NodeId(in.u64("edge source"));
    edge.target = NodeId(in.u64("edge target"));
    edge.info.weight = in.f64("edge weight");
    edge.info.weighted = readBool(in, "edge weighted flag");
    return edge;
  });
  delta.removed_edges = readList(r, "removed edge", 16, [](ByteReader& in) {
    const NodeId a(in.u64("edge source"));
    return EdgeKey(a, NodeId(in.u64("edge target")));
  });
  delta.mesh = readMeshDelta(r);
  return delta;
}

RobotUpdate readRobotUpdate(ByteReader& r) {
  RobotUpdate u;
  u.robot = RobotId(r.u8("robot"));
  u.sequence = r.varint("sequence number");
  u.time_ns = r.svarint("time");
  u.is_snapshot = readBool(r, "snapshot flag");
  u.provided_layers = readU32Varint(r, "provided layers");
  u.graph = readGraphDelta(r);
  u.pose_graph = readList(r, "pose graph edge", kMinPoseEdgeBytes, [](ByteReader& in) {
    PoseGraphEdge e;
    e.from = NodeId(in.u64("edge from"));
    e.to = NodeId(in.u64("edge to"));
    const uint8_t kind = in.u8("edge kind");
    if (kind > 1) in.fail("unknown pose graph edge kind " + std::to_string(kind));
    e.kind = static_cast<PoseGraphEdge::Kind>(kind);
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 4; ++col) T(row, col) = in.f64("edge pose");
    }
    e.T_from_to.matrix() = T;
    for (int row = 0; row < 6; ++row) {
      for (int col = 0; col < 6; ++col) e.information(row, col) = in.f64("edge information");
    }
    return e;
  });
  u.deformation.points = readList(r, "control point", 1 + 24 + 1 + 8, [](ByteReader& in) {
    ControlPoint p;
    p.id = in.varint("control point id");
    p.position = readVector3d(in, "control point position");
    p.time_ns = in.svarint("control point time");
    p.keyframe = NodeId(in.u64("control point keyframe"));
    return p;
  });
  u.deformation.edges = readList(r, "control point edge", 2, [](ByteReader& in) {
    ControlPointEdge e;
    e.from = in.varint("control point edge");
    e.to = in.varint("control point edge");
    return e;
  });
  u.descriptors = readList(r, "descriptor", 8 + 1 + 1, [](ByteReader& in) {
    KeyframeDescriptor d;
    d.keyframe = NodeId(in.u64("descriptor keyframe"));
    d.bow = readList(in, "bag-of-words entry", 5, [](ByteReader& in2) {
      BowEntry b;
      b.word = readU32Varint(in2, "word id");
      b.weight = in2.f32("word weight");
      return b;
    });
    d.keypoints = readList(in, "keypoint", 13, [](ByteReader& in2) {
      Keypoint k;
      for (int i = 0; i < 3; ++i) k.position[i] = in2.f32("keypoint position");
      k.word = readU32Varint(in2, "keypoint word");
      return k;
    });
    return d;
  });
  return u;
}

template <typename T, typename ReadPayload>
Result<T> decodePayload(const RecordView& record, RecordKind expected, const char* what,
                        ReadPayload read_payload) {
  const std::string where = what + std::string(" record at byte ") + std::to_string(record.offset);
  if (record.kind != expected) return Error{where + ": the record holds another kind of data"};
  ByteReader reader(record.payload, record.offset);
  try {
    T value = read_payload(reader);
    if (!reader.atEnd()) reader.fail(std::to_string(reader.remaining()) + " unread bytes");
    return value;
  } catch (const DecodeError& error) {
    return Error{where + ": " + error.what()};
  }
}

}  // namespace

Result<SceneGraph> decodeSceneGraphPayload(const RecordView& record) {
  auto delta =
      decodePayload<GraphDelta>(record, RecordKind::kSceneGraph, "scene graph", readGraphDelta);
  if (!delta) return Error{delta.error()};
  const std::string where = "scene graph record at byte " + std::to_string(record.offset) + ": ";
  if (!delta.value().removed_nodes.empty() || !delta.value().removed_edges.empty() ||
      delta.value().mesh.vertex_start != 0 || delta.value().mesh.face_start != 0) {
    return Error{where + "a scene graph cannot hold removals or mesh offsets"};
  }
  auto graph = graphFromSnapshot(delta.value());
  if (!graph) return Error{where + graph.error()};
  return graph;
}

Result<RobotUpdate> decodeRobotUpdatePayload(const RecordView& record) {
  auto update =
      decodePayload<RobotUpdate>(record, RecordKind::kRobotUpdate, "robot update", readRobotUpdate);
  if (!update) return update;
  if (Status status = validateRobotUpdate(update.value()); !status) {
    return Error{"robot update record at byte " + std::to_string(record.offset) + ": " +
                 status.message()};
  }
  return update;
}

namespace {

template <typename T, typename DecodeRecord>
Result<T> decodeSingle(std::string_view bytes, DecodeRecord decode_record) {
  RecordReader reader(bytes);
  auto record = reader.next();
  if (!record) return Error{record.error()};
  if (!record.value()) return Error{"empty input: no record"};
  auto value = decode_record(*record.value());
  if (!value) return value;
  auto rest = reader.next();
  if (!rest || rest.value()) {
    return Error{"more than one record: expected a single one"};
  }
  return value;
}

}  // namespace

Result<SceneGraph> decodeSceneGraphBinary(std::string_view bytes) {
  return decodeSingle<SceneGraph>(bytes, decodeSceneGraphPayload);
}

Result<GraphDelta> decodeGraphDeltaBinary(std::string_view bytes) {
  return decodeSingle<GraphDelta>(bytes, [](const RecordView& record) {
    return decodePayload<GraphDelta>(record, RecordKind::kGraphDelta, "graph delta",
                                     readGraphDelta);
  });
}

Result<RobotUpdate> decodeRobotUpdateBinary(std::string_view bytes) {
  return decodeSingle<RobotUpdate>(bytes, decodeRobotUpdatePayload);
}

}  // namespace hydra_multi::io
