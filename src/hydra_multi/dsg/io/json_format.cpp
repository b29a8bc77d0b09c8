#include "hydra_multi/dsg/io/json_format.h"

#include "hydra_multi/dsg/io/json_codecs.h"
#include "hydra_multi/dsg/io/json_fields.h"

namespace hydra_multi::io {
namespace {

void checkHeader(const Json& root, const char* format_name) {
  const std::string format = toString(member(root, "format"), "format");
  if (format != format_name) {
    throw DecodeError("format is '" + format + "', expected '" + format_name + "'");
  }
  const int64_t version = toInt64(member(root, "version"), "version");
  if (version != kJsonVersion) {
    throw DecodeError("version " + std::to_string(version) +
                      " is not supported (this build reads " + std::to_string(kJsonVersion) + ")");
  }
}

// Runs `read` on a parsed document, turning every failure into an Error.
template <typename T, typename Read>
Result<T> readRoot(const Json& root, const char* what, Read read) {
  try {
    return read(root);
  } catch (const DecodeError& error) {
    return Error{std::string(what) + ": " + error.what()};
  } catch (const nlohmann::json::exception& error) {
    return Error{std::string(what) + ": " + error.what()};
  }
}

}  // namespace

std::string sceneGraphToJson(const SceneGraph& graph, bool one_line) {
  const GraphDelta snapshot = snapshotOf(graph);
  Json root;
  root["format"] = kSceneGraphFormatName;
  root["version"] = kJsonVersion;
  root["nodes"] = nodesJson(snapshot.nodes);
  root["edges"] = edgesJson(snapshot.edges);
  root["mesh"] = {{"vertices", verticesJson(snapshot.mesh.vertices)},
                  {"faces", facesJson(snapshot.mesh.faces)}};
  return one_line ? root.dump() + "\n" : dumpOneItemPerLine(root);
}

Result<Json> parseJson(const std::string& text, const char* what) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    return Error{std::string(what) + ": invalid JSON at byte " + std::to_string(error.byte) + ": " +
                 error.what()};
  } catch (const nlohmann::json::exception& error) {
    // e.g. out_of_range 406: a number that overflows a double ("1e999").
    return Error{std::string(what) + ": invalid JSON: " + error.what()};
  }
}

Result<SceneGraph> sceneGraphFromJson(const std::string& text) {
  auto root = parseJson(text, "scene graph JSON");
  if (!root) return Error{root.error()};
  return sceneGraphFromJsonValue(root.value());
}

Result<SceneGraph> sceneGraphFromJsonValue(const Json& document) {
  auto snapshot = readRoot<GraphDelta>(document, "scene graph JSON", [](const Json& root) {
    checkHeader(root, kSceneGraphFormatName);
    GraphDelta delta;
    delta.nodes = readArray(member(root, "nodes"), "nodes", readNode);
    delta.edges = readArray(member(root, "edges"), "edges", readEdge);
    const Json& mesh = member(root, "mesh");
    delta.mesh.vertices = readArray(member(mesh, "vertices"), "mesh.vertices", readVertex);
    delta.mesh.faces = readArray(member(mesh, "faces"), "mesh.faces", readFace);
    return delta;
  });
  if (!snapshot) return Error{snapshot.error()};
  auto graph = graphFromSnapshot(snapshot.value());
  if (!graph) return Error{"scene graph JSON: " + graph.error()};
  return graph;
}

std::string robotUpdateToJson(const RobotUpdate& u, bool one_line) {
  Json root;
  root["format"] = kRobotUpdateFormatName;
  root["version"] = kJsonVersion;
  root["robot"] = u.robot.str();
  root["sequence"] = u.sequence;
  root["time_ns"] = u.time_ns;
  root["is_snapshot"] = u.is_snapshot;
  Json layers = Json::array();
  for (uint32_t bit = 1; bit <= kProvidesAll; bit <<= 1) {
    if (u.provided_layers & bit) layers.push_back(providedLayerName(bit));
  }
  root["provided_layers"] = layers;
  Json removed_nodes = Json::array();
  for (const NodeId id : u.graph.removed_nodes) removed_nodes.push_back(id.str());
  Json removed_edges = Json::array();
  for (const EdgeKey& key : u.graph.removed_edges) {
    removed_edges.push_back(Json::array({key.first().str(), key.second().str()}));
  }
  root["graph"] = {{"nodes", nodesJson(u.graph.nodes)},
                   {"removed_nodes", removed_nodes},
                   {"edges", edgesJson(u.graph.edges)},
                   {"removed_edges", removed_edges},
                   {"mesh",
                    {{"vertex_start", u.graph.mesh.vertex_start},
                     {"vertices", verticesJson(u.graph.mesh.vertices)},
                     {"face_start", u.graph.mesh.face_start},
                     {"faces", facesJson(u.graph.mesh.faces)}}}};
  Json pose_graph = Json::array();
  for (const PoseGraphEdge& e : u.pose_graph) {
    pose_graph.push_back(
        {{"from", e.from.str()},
         {"to", e.to.str()},
         {"kind", e.kind == PoseGraphEdge::Kind::kOdometry ? "odometry" : "loop_closure"},
         {"T_from_to", poseJson(e.T_from_to)},
         {"information", informationJson(e.information)}});
  }
  root["pose_graph"] = pose_graph;
  Json points = Json::array();
  for (const ControlPoint& p : u.deformation.points) {
    points.push_back({{"id", p.id},
                      {"position", vec3(p.position)},
                      {"time_ns", p.time_ns},
                      {"keyframe", p.keyframe.str()}});
  }
  Json cp_edges = Json::array();
  for (const ControlPointEdge& e : u.deformation.edges)
    cp_edges.push_back(Json::array({e.from, e.to}));
  root["deformation"] = {{"points", points}, {"edges", cp_edges}};
  Json descriptors = Json::array();
  for (const KeyframeDescriptor& d : u.descriptors) {
    Json bow = Json::array();
    for (const BowEntry& b : d.bow) bow.push_back(Json::array({b.word, floatForJson(b.weight)}));
    Json keypoints = Json::array();
    for (const Keypoint& k : d.keypoints) {
      keypoints.push_back({{"position", vec3f(k.position)}, {"word", k.word}});
    }
    descriptors.push_back({{"keyframe", d.keyframe.str()}, {"bow", bow}, {"keypoints", keypoints}});
  }
  root["descriptors"] = descriptors;
  return one_line ? root.dump() + "\n" : dumpOneItemPerLine(root);
}

Result<RobotUpdate> robotUpdateFromJson(const std::string& text) {
  auto document = parseJson(text, "robot update JSON");
  if (!document) return Error{document.error()};
  auto update = readRoot<RobotUpdate>(document.value(), "robot update JSON", [](const Json& root) {
    checkHeader(root, kRobotUpdateFormatName);
    RobotUpdate u;
    const std::string robot = toString(member(root, "robot"), "robot");
    const auto robot_id = RobotId::parse(robot);
    if (!robot_id) throw DecodeError("key 'robot': '" + robot + "' is not a robot name");
    u.robot = *robot_id;
    u.sequence = toUint64(member(root, "sequence"), "sequence");
    u.time_ns = toInt64(member(root, "time_ns"), "time_ns");
    u.is_snapshot = toBool(member(root, "is_snapshot"), "is_snapshot");
    u.provided_layers = 0;
    for (const std::string& name : readArray(member(root, "provided_layers"), "provided_layers",
                                             [](const Json& v) { return toString(v, "layer"); })) {
      uint32_t bit = 1;
      while (bit <= kProvidesAll && name != providedLayerName(bit)) bit <<= 1;
      if (bit > kProvidesAll) throw DecodeError("provided_layers: unknown layer '" + name + "'");
      u.provided_layers |= bit;
    }
    const Json& graph = member(root, "graph");
    u.graph.nodes = readArray(member(graph, "nodes"), "graph.nodes", readNode);
    u.graph.removed_nodes = readArray(member(graph, "removed_nodes"), "graph.removed_nodes",
                                      [](const Json& v) { return toNodeId(v, "node"); });
    u.graph.edges = readArray(member(graph, "edges"), "graph.edges", readEdge);
    u.graph.removed_edges =
        readArray(member(graph, "removed_edges"), "graph.removed_edges", readEdgeKey);
    const Json& mesh = member(graph, "mesh");
    u.graph.mesh.vertex_start = toUint64(member(mesh, "vertex_start"), "vertex_start");
    u.graph.mesh.vertices = readArray(member(mesh, "vertices"), "graph.mesh.vertices", readVertex);
    u.graph.mesh.face_start = toUint64(member(mesh, "face_start"), "face_start");
    u.graph.mesh.faces = readArray(member(mesh, "faces"), "graph.mesh.faces", readFace);
    u.pose_graph = readArray(member(root, "pose_graph"), "pose_graph", [](const Json& j) {
      PoseGraphEdge e;
      e.from = toNodeId(member(j, "from"), "from");
      e.to = toNodeId(member(j, "to"), "to");
      const std::string kind = toString(member(j, "kind"), "kind");
      if (kind != "odometry" && kind != "loop_closure") {
        throw DecodeError("key 'kind': '" + kind + "' is neither odometry nor loop_closure");
      }
      e.kind =
          kind == "odometry" ? PoseGraphEdge::Kind::kOdometry : PoseGraphEdge::Kind::kLoopClosure;
      e.T_from_to = readPose(member(j, "T_from_to"), "T_from_to");
      e.information = readInformation(member(j, "information"));
      return e;
    });
    const Json& deformation = member(root, "deformation");
    u.deformation.points =
        readArray(member(deformation, "points"), "deformation.points", [](const Json& j) {
          return ControlPoint{toUint64(member(j, "id"), "id"),
                              toVector3d(member(j, "position"), "position"),
                              toInt64(member(j, "time_ns"), "time_ns"),
                              toNodeId(member(j, "keyframe"), "keyframe")};
        });
    u.deformation.edges =
        readArray(member(deformation, "edges"), "deformation.edges", [](const Json& j) {
          if (!j.is_array() || j.size() != 2) throw DecodeError("expected [from, to]");
          return ControlPointEdge{toUint64(j[0], "from"), toUint64(j[1], "to")};
        });
    u.descriptors = readArray(member(root, "descriptors"), "descriptors", [](const Json& j) {
      KeyframeDescriptor d;
      d.keyframe = toNodeId(member(j, "keyframe"), "keyframe");
      d.bow = readArray(member(j, "bow"), "bow", [](const Json& b) {
        if (!b.is_array() || b.size() != 2) throw DecodeError("expected [word, weight]");
        return BowEntry{toUint32(b[0], "word"), toFloat(b[1], "weight")};
      });
      d.keypoints = readArray(member(j, "keypoints"), "keypoints", [](const Json& k) {
        return Keypoint{toVector3f(member(k, "position"), "position"),
                        toUint32(member(k, "word"), "word")};
      });
      return d;
    });
    return u;
  });
  if (!update) return update;
  if (Status status = validateRobotUpdate(update.value()); !status) {
    return Error{"robot update JSON: " + status.message()};
  }
  return update;
}

bool isOurSceneGraphJson(const Json& root) {
  return root.is_object() && root.contains("format") && root["format"] == kSceneGraphFormatName;
}

}  // namespace hydra_multi::io
