// `hydra-multi info FILE [--json]`: what a scene-graph file or a robot-update stream holds.

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/dsg/graph_summary.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/robot_stream.h"

namespace hydra_multi::apps {
namespace {

using Json = nlohmann::ordered_json;

Json layersJson(const std::array<size_t, kAllLayers.size()>& counts) {
  Json j;
  for (const Layer layer : kAllLayers) j[layerName(layer)] = counts[static_cast<size_t>(layer)];
  return j;
}

void printGraph(const std::string& path, const GraphSummary& s,
                const std::map<std::string, size_t>& unread, bool json) {
  if (json) {
    Json robots = Json::object();
    for (const auto& [robot, r] : s.robots) {
      robots[robot.str()] = {{"nodes", r.numNodes()},
                             {"layers", layersJson(r.nodes_per_layer)},
                             {"mesh_vertices", r.mesh_vertices}};
    }
    const Json j = {{"file", path},
                    {"kind", "scene graph"},
                    {"nodes", s.nodes},
                    {"edges", s.edges},
                    {"layers", layersJson(s.nodes_per_layer)},
                    {"mesh_vertices", s.mesh_vertices},
                    {"mesh_faces", s.mesh_faces},
                    {"robots", robots},
                    {"keys_not_read", unread}};
    std::cout << j.dump() << "\n";
    return;
  }
  std::cout << path << ": scene graph\n"
            << "  nodes " << s.nodes << ", edges " << s.edges << "\n  ";
  for (const Layer layer : kAllLayers) {
    std::cout << layerName(layer) << " " << s.nodes_per_layer[static_cast<size_t>(layer)]
              << (layer == Layer::kBuildings ? "\n" : ", ");
  }
  std::cout << "  mesh: " << s.mesh_vertices << " vertices, " << s.mesh_faces << " faces\n";
  for (const auto& [robot, r] : s.robots) {
    std::cout << "  robot " << robot.str() << ": "
              << r.nodes_per_layer[static_cast<size_t>(Layer::kAgents)] << " agent poses, "
              << r.numNodes() << " nodes, " << r.mesh_vertices << " mesh vertices\n";
  }
}

struct StreamRobot {
  size_t updates = 0, snapshots = 0, nodes = 0, removed_nodes = 0, edges = 0, mesh_vertices = 0;
  size_t pose_graph_edges = 0, descriptors = 0;
  uint64_t first_sequence = 0, last_sequence = 0;
  int64_t first_time_ns = 0, last_time_ns = 0;
  std::unique_ptr<RobotStreamReplay> replay;  // the station's order rule over its updates
};

// The stream's updates per robot and its damaged records; 1 when there are any, so a script that
// checks a recording notices.
int printStream(const std::string& path, const std::vector<RobotUpdate>& updates,
                const std::vector<std::string>& damaged, bool json) {
  std::map<RobotId, StreamRobot> robots;
  for (const RobotUpdate& u : updates) {
    StreamRobot& r = robots[u.robot];
    if (r.updates == 0) {
      r.first_sequence = u.sequence;
      r.first_time_ns = u.time_ns;
      r.replay = std::make_unique<RobotStreamReplay>(u.robot, io::robotUpdateDigest);
    }
    r.replay->add(u);
    ++r.updates;
    r.snapshots += u.is_snapshot ? 1 : 0;
    r.nodes += u.graph.nodes.size();
    r.removed_nodes += u.graph.removed_nodes.size();
    r.edges += u.graph.edges.size();
    r.mesh_vertices += u.graph.mesh.vertices.size();
    r.pose_graph_edges += u.pose_graph.size();
    r.descriptors += u.descriptors.size();
    r.last_sequence = u.sequence;
    r.last_time_ns = u.time_ns;
  }
  if (json) {
    Json per_robot = Json::object();
    for (const auto& [robot, r] : robots) {
      per_robot[robot.str()] = {{"updates", r.updates},
                                {"snapshots", r.snapshots},
                                {"first_sequence", r.first_sequence},
                                {"last_sequence", r.last_sequence},
                                {"first_time_ns", r.first_time_ns},
                                {"last_time_ns", r.last_time_ns},
                                {"nodes_sent", r.nodes},
                                {"nodes_removed", r.removed_nodes},
                                {"edges_sent", r.edges},
                                {"mesh_vertices_sent", r.mesh_vertices},
                                {"pose_graph_edges", r.pose_graph_edges},
                                {"descriptors", r.descriptors},
                                {"updates_applied", r.replay->order().counts().appliedTotal()},
                                {"updates_rejected", r.replay->order().counts().rejected},
                                {"updates_behind_gap", r.replay->order().counts().behindGap()}};
    }
    std::cout << Json{{"file", path},
                      {"kind", "robot updates"},
                      {"updates", updates.size()},
                      {"robots", per_robot},
                      {"damaged_records", damaged}}
                     .dump()
              << "\n";
    return damaged.empty() ? 0 : 1;
  }
  std::cout << path << ": " << updates.size() << " robot updates\n";
  for (const auto& [robot, r] : robots) {
    std::cout << "  robot " << robot.str() << ": " << r.updates << " updates (" << r.snapshots
              << " snapshots), sequence " << r.first_sequence << ".." << r.last_sequence << ", "
              << r.nodes << " nodes sent, " << r.removed_nodes << " removed, " << r.edges
              << " edges, " << r.mesh_vertices << " mesh vertices, " << r.pose_graph_edges
              << " pose-graph edges, " << r.descriptors << " descriptors\n";
    // As the station would apply them; the damaged records are this robot's when it is alone.
    std::cout << "  "
              << describeStream(robot, &r.replay->order(), robots.size() == 1 ? damaged.size() : 0)
              << "\n";
  }
  if (damaged.empty()) return 0;
  std::cout << damaged.size() << (damaged.size() == 1 ? " damaged record" : " damaged records")
            << " (left out above):\n";
  for (const std::string& d : damaged) std::cout << "  " << d << "\n";
  return 1;
}

// Whether a .dsgb file holds robot-update records (rather than a scene graph): the kind of its
// first intact record, so that a stream whose first record is damaged is still a stream.
bool isUpdateStream(const std::string& path) {
  auto bytes = io::readFile(path);
  if (!bytes) return false;
  io::RecordReader reader(bytes.value());
  for (;;) {
    auto record = reader.next();
    if (record) return record.value() && record.value()->kind == io::RecordKind::kRobotUpdate;
    if (!reader.resynchronize()) return false;
  }
}

}  // namespace

int runInfo(const InfoOptions& options) {
  const auto format = io::formatFromPath(options.path);
  if (format == io::FileFormat::kBinary && isUpdateStream(options.path)) {
    std::vector<std::string> damaged;
    auto updates = io::loadRobotUpdates(options.path, &damaged);
    if (!updates) return fail(updates.error());
    return printStream(options.path, updates.value(), damaged, options.json);
  }
  std::map<std::string, size_t> unread;
  auto graph = io::loadSceneGraph(options.path, &unread);
  if (!graph) return fail(graph.error());
  if (!unread.empty() && !options.json)
    std::cerr << "hydra-multi: note: " << io::describeUnread(options.path, unread) << "\n";
  printGraph(options.path, summarize(graph.value()), unread, options.json);
  return 0;
}

}  // namespace hydra_multi::apps
