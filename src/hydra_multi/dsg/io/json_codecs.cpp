// JSON codecs of the scene-graph parts our JSON documents share (json_format.cpp).

#include "hydra_multi/dsg/io/json_codecs.h"

namespace hydra_multi::io {
namespace {

Json color(const Color& c) { return Json::array({c.r, c.g, c.b}); }

Json semanticJson(const SemanticAttributes& s, Json& j) {
  j["label"] = s.label;
  j["name"] = s.name;
  j["color"] = color(s.color);
  if (s.bounding_box) {
    j["bounding_box"] = {{"min", vec3(s.bounding_box->min)}, {"max", vec3(s.bounding_box->max)}};
  } else {
    j["bounding_box"] = nullptr;
  }
  return j;
}

Json nodeJson(const Node& node) {
  Json j;
  j["id"] = node.id.str();
  j["layer"] = layerName(node.layer());
  j["position"] = vec3(node.position);
  j["last_update_time_ns"] = node.last_update_time_ns;
  j["is_active"] = node.is_active;
  if (const auto* agent = node.find<AgentAttributes>()) {
    const Eigen::Quaterniond& q = agent->orientation;
    j["orientation"] = {{"w", q.w()}, {"x", q.x()}, {"y", q.y()}, {"z", q.z()}};
    j["timestamp_ns"] = agent->timestamp_ns;
    j["keyframe_id"] = agent->keyframe_id;
    return j;
  }
  semanticJson(*node.semantic(), j);
  if (const auto* object = node.find<ObjectAttributes>())
    j["mesh_vertices"] = object->mesh_vertices;
  if (const auto* place = node.find<PlaceAttributes>()) {
    j["distance"] = place->distance;
    j["mesh_vertices"] = place->mesh_vertices;
  }
  return j;
}

Json edgeJson(const Edge& edge) {
  return {{"source", edge.source.str()},
          {"target", edge.target.str()},
          {"weight", edge.info.weight},
          {"weighted", edge.info.weighted}};
}

Json vertexJson(const MeshVertex& v) {
  Json j;
  j["position"] = vec3f(v.position);
  j["color"] = color(v.color);
  j["label"] = v.label == MeshVertex::kUnlabeled ? Json(nullptr) : Json(v.label);
  j["robot"] = v.robot.str();
  j["time_ns"] = v.time_ns;
  return j;
}

Color readColor(const Json& j) {
  const Json& c = member(j, "color");
  if (!c.is_array() || c.size() != 3) throw DecodeError("key 'color': expected [r, g, b]");
  return {toUint8(c[0], "color"), toUint8(c[1], "color"), toUint8(c[2], "color")};
}

void readSemantic(const Json& j, SemanticAttributes& s) {
  s.label = toUint32(member(j, "label"), "label");
  s.name = toString(member(j, "name"), "name");
  s.color = readColor(j);
  const Json& box = member(j, "bounding_box");
  if (!box.is_null()) {
    s.bounding_box = BoundingBox{toVector3d(member(box, "min"), "bounding_box.min"),
                                 toVector3d(member(box, "max"), "bounding_box.max")};
  }
}

std::vector<uint64_t> readIndices(const Json& j, const char* key) {
  return readArray(member(j, key), key, [key](const Json& v) { return toUint64(v, key); });
}

}  // namespace

Json vec3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json vec3f(const Eigen::Vector3f& v) {
  return Json::array({floatForJson(v.x()), floatForJson(v.y()), floatForJson(v.z())});
}

Json nodesJson(const std::vector<Node>& nodes) {
  Json j = Json::array();
  for (const Node& node : nodes) j.push_back(nodeJson(node));
  return j;
}

Json edgesJson(const std::vector<Edge>& edges) {
  Json j = Json::array();
  for (const Edge& edge : edges) j.push_back(edgeJson(edge));
  return j;
}

Json verticesJson(const std::vector<MeshVertex>& vertices) {
  Json j = Json::array();
  for (const MeshVertex& v : vertices) j.push_back(vertexJson(v));
  return j;
}

Json facesJson(const std::vector<MeshFace>& faces) {
  Json j = Json::array();
  for (const MeshFace& f : faces) j.push_back(Json::array({f[0], f[1], f[2]}));
  return j;
}

Json poseJson(const Eigen::Isometry3d& T) {
  Json rows = Json::array();
  for (int r = 0; r < 3; ++r) {
    rows.push_back(Json::array({T(r, 0), T(r, 1), T(r, 2), T(r, 3)}));
  }
  return rows;
}

Json informationJson(const Matrix6d& info) {
  Json rows = Json::array();
  for (int r = 0; r < 6; ++r) {
    Json row = Json::array();
    for (int c = 0; c < 6; ++c) row.push_back(info(r, c));
    rows.push_back(row);
  }
  return rows;
}

Node readNode(const Json& j) {
  const NodeId id = toNodeId(member(j, "id"), "id");
  const std::string layer_name = toString(member(j, "layer"), "layer");
  const auto layer = layerFromName(layer_name);
  if (!layer) throw DecodeError("node " + id.str() + ": unknown layer '" + layer_name + "'");
  Node node = makeNode(id, *layer, toVector3d(member(j, "position"), "position"));
  node.last_update_time_ns = toInt64(member(j, "last_update_time_ns"), "last_update_time_ns");
  node.is_active = toBool(member(j, "is_active"), "is_active");
  if (auto* agent = node.find<AgentAttributes>()) {
    const Json& q = member(j, "orientation");
    agent->orientation = Eigen::Quaterniond(
        toDouble(member(q, "w"), "orientation.w"), toDouble(member(q, "x"), "orientation.x"),
        toDouble(member(q, "y"), "orientation.y"), toDouble(member(q, "z"), "orientation.z"));
    agent->timestamp_ns = toInt64(member(j, "timestamp_ns"), "timestamp_ns");
    agent->keyframe_id = toUint64(member(j, "keyframe_id"), "keyframe_id");
    return node;
  }
  readSemantic(j, *node.semantic());
  if (auto* object = node.find<ObjectAttributes>()) {
    object->mesh_vertices = readIndices(j, "mesh_vertices");
  }
  if (auto* place = node.find<PlaceAttributes>()) {
    place->distance = toDouble(member(j, "distance"), "distance");
    place->mesh_vertices = readIndices(j, "mesh_vertices");
  }
  return node;
}

Edge readEdge(const Json& j) {
  return {toNodeId(member(j, "source"), "source"), toNodeId(member(j, "target"), "target"),
          EdgeAttributes{toDouble(member(j, "weight"), "weight"),
                         toBool(member(j, "weighted"), "weighted")}};
}

MeshVertex readVertex(const Json& j) {
  MeshVertex v;
  v.position = toVector3f(member(j, "position"), "position");
  v.color = readColor(j);
  const Json& label = member(j, "label");
  v.label = label.is_null() ? MeshVertex::kUnlabeled : toUint32(label, "label");
  const std::string robot = toString(member(j, "robot"), "robot");
  const auto robot_id = RobotId::parse(robot);
  if (!robot_id) throw DecodeError("key 'robot': '" + robot + "' is not a robot name");
  v.robot = *robot_id;
  v.time_ns = toInt64(member(j, "time_ns"), "time_ns");
  return v;
}

MeshFace readFace(const Json& j) {
  const auto v = toNumbers(j, "face", 3);
  MeshFace face;
  for (size_t i = 0; i < 3; ++i) face[i] = toUint32(j[i], "face");
  return face;
}

EdgeKey readEdgeKey(const Json& j) {
  if (!j.is_array() || j.size() != 2) throw DecodeError("expected [source, target]");
  return {toNodeId(j[0], "source"), toNodeId(j[1], "target")};
}

Eigen::Isometry3d readPose(const Json& j, const char* key) {
  if (!j.is_array() || j.size() != 3)
    throw DecodeError(std::string("key '") + key + "': expected 3 rows");
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  for (size_t r = 0; r < 3; ++r) {
    const auto row = toNumbers(j[r], key, 4);
    for (size_t c = 0; c < 4; ++c) T(static_cast<int>(r), static_cast<int>(c)) = row[c];
  }
  Eigen::Isometry3d result;
  result.matrix() = T;
  return result;
}

Matrix6d readInformation(const Json& j) {
  if (!j.is_array() || j.size() != 6) throw DecodeError("key 'information': expected 6 rows");
  Matrix6d info;
  for (size_t r = 0; r < 6; ++r) {
    const auto row = toNumbers(j[r], "information", 6);
    for (size_t c = 0; c < 6; ++c) info(static_cast<int>(r), static_cast<int>(c)) = row[c];
  }
  return info;
}

}  // namespace hydra_multi::io
