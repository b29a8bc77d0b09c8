#include "hydra_multi/dsg/io/spark_json.h"

#include <cmath>
#include <limits>

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
    // Legacy: [r, g, b]; Spark-DSG 1.0.3 and later: {r, g, b, a} (alpha dropped).
    const Json& c = member(a, "color");
    if (c.is_object()) {
      s.color = {toUint8(member(c, "r"), "color.r"), toUint8(member(c, "g"), "color.g"),
                 toUint8(member(c, "b"), "color.b")};
    } else if (c.is_array() && c.size() >= 3) {
      s.color = {toUint8(c[0], "color"), toUint8(c[1], "color"), toUint8(c[2], "color")};
    } else {
      throw DecodeError("key 'color': expected [r, g, b] or {r, g, b, a}");
    }
  }
  if (hasMember(a, "bounding_box")) {
    // Legacy: min and max; Spark-DSG 1.0.3 and later: dimensions about world_P_center (an
    // axis-aligned box of them; a rotated box's rotation is not kept).
    const Json& box = member(a, "bounding_box");
    const std::string type = toString(member(box, "type"), "bounding_box.type");
    if (type == "AABB" || type == "OBB" || type == "RAABB") {
      if (hasMember(box, "dimensions")) {
        const Eigen::Vector3d half =
            0.5 * toVector3d(member(box, "dimensions"), "bounding_box.dimensions");
        const Eigen::Vector3d centre =
            toVector3d(member(box, "world_P_center"), "bounding_box.world_P_center");
        s.bounding_box = BoundingBox{centre - half, centre + half};
        if (hasMember(box, "world_R_center")) member(box, "world_R_center");
      } else if (type == "AABB") {
        s.bounding_box = BoundingBox{toVector3d(member(box, "min"), "bounding_box.min"),
                                     toVector3d(member(box, "max"), "bounding_box.max")};
      } else {
        throw DecodeError("bounding box of type " + type + " without dimensions");
      }
    } else if (type != "INVALID") {
      throw DecodeError("bounding box type '" + type +
                        "' is not supported (AABB, OBB, RAABB or INVALID)");
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
  // Spark-DSG 1.1 names each node's partition; agents are in their prefix's, the rest in 0.
  const uint64_t partition =
      hasMember(j, "partition") ? toUint32(member(j, "partition"), "partition") : 0;
  Layer layer;
  switch (layer_id) {
    case kAgentsAndObjects:
      layer = hasMember(j, "prefix") || partition != 0 ? Layer::kAgents : Layer::kObjects;
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
  if (layer != Layer::kAgents && partition != 0) {
    throw DecodeError("node " + id.str() + ": layer " + std::to_string(layer_id) + " partition " +
                      std::to_string(partition) +
                      " is not supported (only agents have partitions)");
  }
  Node node = makeNode(id, layer, toVector3d(member(a, "position"), "position"));
  if (hasMember(a, "last_update_time_ns")) {
    // Spark-DSG declares it uint64; an unset stamp above 2^63 - 1 is taken as 0.
    const uint64_t stamp = toUint64(member(a, "last_update_time_ns"), "last_update_time_ns");
    node.last_update_time_ns =
        stamp > uint64_t(std::numeric_limits<int64_t>::max()) ? 0 : static_cast<int64_t>(stamp);
  }
  if (hasMember(a, "is_active")) node.is_active = toBool(member(a, "is_active"), "is_active");
  if (auto* agent = node.find<AgentAttributes>()) {
    const uint64_t prefix =
        hasMember(j, "prefix") ? toUint8(member(j, "prefix"), "prefix") : partition;
    if (prefix != static_cast<uint8_t>(id.category())) {
      throw DecodeError("node " + id.str() + ": " +
                        (hasMember(j, "prefix") ? "prefix " : "partition ") +
                        std::to_string(prefix) + " differs from the id's category");
    }
    agent->orientation = readQuaternion(member(a, "world_R_body"), "world_R_body");
    // Legacy: the node's "timestamp"; Spark-DSG 1.1: the attributes' (ns).
    agent->timestamp_ns = hasMember(a, "timestamp") ? toInt64(member(a, "timestamp"), "timestamp")
                                                    : toInt64(member(j, "timestamp"), "timestamp");
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

// Spark-DSG 1.1's mesh: points, optional colours ({r, g, b, a}), labels and last-seen stamps,
// faces (first-seen stamps are not kept).
MeshDelta readMesh(const Json& m) {
  MeshDelta mesh;
  mesh.vertices = readArray(member(m, "points"), "mesh.points", [](const Json& p) {
    MeshVertex v;
    v.position = toVector3f(p, "mesh.points");
    return v;
  });
  const auto perVertex = [&](const char* key, const char* has, auto&& read) {
    if (hasMember(m, has) && !toBool(member(m, has), has)) return;
    const Json& values = toArray(member(m, key), key);
    if (values.size() != mesh.vertices.size())
      throw DecodeError(std::string("mesh.") + key + ": " + std::to_string(values.size()) +
                        " values for " + std::to_string(mesh.vertices.size()) + " points");
    for (size_t i = 0; i < values.size(); ++i) read(values[i], mesh.vertices[i]);
  };
  perVertex("colors", "has_colors", [](const Json& c, MeshVertex& v) {
    v.color = {toUint8(member(c, "r"), "mesh.colors"), toUint8(member(c, "g"), "mesh.colors"),
               toUint8(member(c, "b"), "mesh.colors")};
  });
  perVertex("labels", "has_labels",
            [](const Json& l, MeshVertex& v) { v.label = toUint32(l, "mesh.labels"); });
  perVertex("stamps", "has_timestamps", [](const Json& t, MeshVertex& v) {
    const uint64_t stamp = toUint64(t, "mesh.stamps");
    v.time_ns = stamp > uint64_t(std::numeric_limits<int64_t>::max()) ? 0 : int64_t(stamp);
  });
  if (hasMember(m, "first_seen_stamps")) member(m, "first_seen_stamps");
  if (hasMember(m, "header")) member(m, "header");
  mesh.faces = readArray(member(m, "faces"), "mesh.faces", [](const Json& f) {
    const std::vector<double> i = toNumbers(f, "mesh.faces", 3);
    for (const double x : i) {
      if (x < 0 || x > double(std::numeric_limits<uint32_t>::max()) || x != std::floor(x))
        throw DecodeError("mesh.faces: " + std::to_string(x) + " is not a vertex index");
    }
    return MeshFace{uint32_t(i[0]), uint32_t(i[1]), uint32_t(i[2])};
  });
  return mesh;
}

}  // namespace

Result<SceneGraph> sceneGraphFromSparkJsonValue(const Json& root) {
  GraphDelta snapshot;
  try {
    snapshot.nodes = readArray(member(root, "nodes"), "nodes", readNode);
    snapshot.edges = readArray(member(root, "edges"), "edges", readEdge);
    if (hasMember(root, "mesh")) snapshot.mesh = readMesh(member(root, "mesh"));
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
