#include "hydra_multi/dsg/io/spark_json.h"

#include "hydra_multi/dsg/io/json_fields.h"
#include "hydra_multi/dsg/io/json_format.h"

namespace hydra_multi::io {
namespace {

constexpr int kAgentsAndObjects = 2;
constexpr int kPlaces = 3;
constexpr int kRooms = 4;
constexpr int kBuildings = 5;

Json quaternionJson(const Eigen::Quaterniond& q) {
  return {{"w", q.w()}, {"x", q.x()}, {"y", q.y()}, {"z", q.z()}};
}

Eigen::Quaterniond readQuaternion(const Json& j, const char* key) {
  return Eigen::Quaterniond(toDouble(member(j, "w"), key), toDouble(member(j, "x"), key),
                            toDouble(member(j, "y"), key), toDouble(member(j, "z"), key));
}

Json vec3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json boxJson(const std::optional<BoundingBox>& box) {
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  return {{"max", vec3(box ? box->max : zero)},
          {"min", vec3(box ? box->min : zero)},
          {"type", box ? "AABB" : "INVALID"},
          {"world_P_center", vec3(box ? box->center() : zero)},
          {"world_R_center", quaternionJson(Eigen::Quaterniond::Identity())}};
}

void writeSemantic(const SemanticAttributes& s, Json& a) {
  a["bounding_box"] = boxJson(s.bounding_box);
  a["color"] = Json::array({s.color.r, s.color.g, s.color.b});
  a["name"] = s.name;
  a["semantic_label"] = s.label;
}

Json nodeJson(const Node& node) {
  Json a;
  a["is_active"] = node.is_active;
  a["last_update_time_ns"] = node.last_update_time_ns;
  a["position"] = vec3(node.position);
  Json j;
  j["id"] = node.id.value();
  switch (node.layer()) {
    case Layer::kAgents: {
      const auto& agent = *node.find<AgentAttributes>();
      a["type"] = "AgentNodeAttributes";
      a["world_R_body"] = quaternionJson(agent.orientation);
      a["external_key"] = agent.keyframe_id;
      a["dbow_ids"] = nullptr;
      a["dbow_values"] = nullptr;
      j["layer"] = kAgentsAndObjects;
      j["prefix"] = static_cast<uint8_t>(node.id.category());
      j["timestamp"] = agent.timestamp_ns;
      break;
    }
    case Layer::kObjects: {
      const auto& object = *node.find<ObjectAttributes>();
      writeSemantic(object.semantic, a);
      a["type"] = "ObjectNodeAttributes";
      a["mesh_connections"] = object.mesh_vertices;
      a["registered"] = true;
      a["world_R_object"] = quaternionJson(Eigen::Quaterniond::Identity());
      j["layer"] = kAgentsAndObjects;
      break;
    }
    case Layer::kPlaces: {
      const auto& place = *node.find<PlaceAttributes>();
      writeSemantic(place.semantic, a);
      a["type"] = "PlaceNodeAttributes";
      a["distance"] = place.distance;
      a["pcl_mesh_connections"] = place.mesh_vertices;
      a["num_basis_points"] = 0;
      a["voxblox_mesh_connections"] = Json::array();
      a["deformation_connections"] = Json::array();
      a["mesh_vertex_labels"] = Json::array();
      j["layer"] = kPlaces;
      break;
    }
    case Layer::kRooms:
      writeSemantic(node.find<RoomAttributes>()->semantic, a);
      a["type"] = "RoomNodeAttributes";
      j["layer"] = kRooms;
      break;
    case Layer::kBuildings:
      writeSemantic(node.find<BuildingAttributes>()->semantic, a);
      a["type"] = "SemanticNodeAttributes";
      j["layer"] = kBuildings;
      break;
  }
  j["attributes"] = a;
  return j;
}

void readSemantic(const Json& a, SemanticAttributes& s) {
  if (hasMember(a, "semantic_label"))
    s.label = toUint32(member(a, "semantic_label"), "semantic_label");
  if (hasMember(a, "name")) s.name = toString(member(a, "name"), "name");
  if (hasMember(a, "color")) {
    const Json& c = member(a, "color");
    if (!c.is_array() || c.size() < 3) throw DecodeError("key 'color': expected [r, g, b]");
    s.color = {toUint8(c[0], "color"), toUint8(c[1], "color"), toUint8(c[2], "color")};
  }
  if (hasMember(a, "bounding_box")) {
    const Json& box = member(a, "bounding_box");
    const std::string type = toString(member(box, "type"), "bounding_box.type");
    if (type == "AABB") {
      s.bounding_box = BoundingBox{toVector3d(member(box, "min"), "bounding_box.min"),
                                   toVector3d(member(box, "max"), "bounding_box.max")};
    } else if (type != "INVALID") {
      throw DecodeError("bounding box type '" + type + "' is not supported (AABB or INVALID)");
    }
  }
}

std::vector<uint64_t> readIndices(const Json& a, const char* key) {
  if (!hasMember(a, key) || member(a, key).is_null()) return {};
  return readArray(member(a, key), key, [key](const Json& v) { return toUint64(v, key); });
}

Node readNode(const Json& j) {
  const NodeId id(toUint64(member(j, "id"), "id"));
  const int64_t layer_id = toInt64(member(j, "layer"), "layer");
  const Json& a = member(j, "attributes");
  Layer layer;
  switch (layer_id) {
    case kAgentsAndObjects:
      layer = hasMember(j, "prefix") ? Layer::kAgents : Layer::kObjects;
      break;
    case kPlaces:
      layer = Layer::kPlaces;
      break;
    case kRooms:
      layer = Layer::kRooms;
      break;
    case kBuildings:
      layer = Layer::kBuildings;
      break;
    default:
      throw DecodeError("node " + id.str() + ": layer " + std::to_string(layer_id) +
                        " is not supported (2 agents/objects, 3 places, 4 rooms, 5 buildings)");
  }
  Node node = makeNode(id, layer, toVector3d(member(a, "position"), "position"));
  if (hasMember(a, "last_update_time_ns")) {
    node.last_update_time_ns = toInt64(member(a, "last_update_time_ns"), "last_update_time_ns");
  }
  if (hasMember(a, "is_active")) node.is_active = toBool(member(a, "is_active"), "is_active");
  if (auto* agent = node.find<AgentAttributes>()) {
    const uint8_t prefix = toUint8(member(j, "prefix"), "prefix");
    if (prefix != static_cast<uint8_t>(id.category())) {
      throw DecodeError("node " + id.str() + ": prefix " + std::to_string(prefix) +
                        " differs from the id's category");
    }
    agent->orientation = readQuaternion(member(a, "world_R_body"), "world_R_body");
    agent->timestamp_ns = toInt64(member(j, "timestamp"), "timestamp");
    if (hasMember(a, "external_key")) {
      agent->keyframe_id = toUint64(member(a, "external_key"), "external_key");
    }
    return node;
  }
  readSemantic(a, *node.semantic());
  if (auto* object = node.find<ObjectAttributes>()) {
    object->mesh_vertices = readIndices(a, "mesh_connections");
  }
  if (auto* place = node.find<PlaceAttributes>()) {
    place->distance = toDouble(member(a, "distance"), "distance");
    place->mesh_vertices = readIndices(a, "pcl_mesh_connections");
  }
  return node;
}

Edge readEdge(const Json& j) {
  Edge edge{NodeId(toUint64(member(j, "source"), "source")),
            NodeId(toUint64(member(j, "target"), "target")),
            {}};
  if (hasMember(j, "info")) {
    const Json& info = member(j, "info");
    if (hasMember(info, "weight"))
      edge.info.weight = toDouble(member(info, "weight"), "info.weight");
    if (hasMember(info, "weighted")) {
      edge.info.weighted = toBool(member(info, "weighted"), "info.weighted");
    }
  }
  return edge;
}

}  // namespace

Result<SceneGraph> sceneGraphFromSparkJsonValue(const Json& root) {
  GraphDelta snapshot;
  try {
    snapshot.nodes = readArray(member(root, "nodes"), "nodes", readNode);
    snapshot.edges = readArray(member(root, "edges"), "edges", readEdge);
  } catch (const DecodeError& error) {
    return Error{std::string("Spark-DSG JSON: ") + error.what()};
  } catch (const nlohmann::json::exception& error) {
    return Error{std::string("Spark-DSG JSON: ") + error.what()};
  }
  auto graph = graphFromSnapshot(snapshot);
  if (!graph) return Error{"Spark-DSG JSON: " + graph.error()};
  return graph;
}

Result<SceneGraph> sceneGraphFromSparkJson(const std::string& text) {
  auto root = parseJson(text, "Spark-DSG JSON");
  if (!root) return Error{root.error()};
  return sceneGraphFromSparkJsonValue(root.value());
}

std::string sceneGraphToSparkJson(const SceneGraph& graph) {
  Json nodes = Json::array();
  for (const auto& [id, node] : graph.nodes()) nodes.push_back(nodeJson(node));
  Json edges = Json::array();
  for (const auto& [key, info] : graph.edges()) {
    edges.push_back(
        {{"info",
          {{"type", "EdgeAttributes"}, {"weight", info.weight}, {"weighted", info.weighted}}},
         {"source", key.first().value()},
         {"target", key.second().value()}});
  }
  Json root;
  root["directed"] = false;
  root["edges"] = edges;
  root["layer_ids"] = Json::array({kAgentsAndObjects, kPlaces, kRooms, kBuildings});
  root["mesh_edges"] = Json::array();
  root["mesh_layer_id"] = 1;
  root["multigraph"] = false;
  root["nodes"] = nodes;
  return root.dump() + "\n";
}

}  // namespace hydra_multi::io
