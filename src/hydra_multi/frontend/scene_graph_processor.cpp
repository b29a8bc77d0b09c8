#include "hydra_multi/frontend/scene_graph_processor.h"

#include <cstdlib>
#include <functional>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/binary_format.h"

namespace hydra_multi {
namespace {

std::string where(const RobotUpdate& update) {
  return "robot " + update.robot.str() + " update " + std::to_string(update.sequence);
}

}  // namespace

SceneGraphProcessor::SceneGraphProcessor(ProcessorOptions options, Logger log)
    : options_(options), log_(std::move(log)) {}

std::optional<NodeId> SceneGraphProcessor::toStation(RobotId robot, NodeId robot_side) {
  if (robot_side.isStation() || robot_side.index() > NodeId::kMaxStationIndex || !robot.isValid())
    return std::nullopt;
  return NodeId::station(robot_side.category(), robot, robot_side.index());
}

std::optional<std::pair<RobotId, NodeId>> SceneGraphProcessor::toRobotSide(NodeId station) {
  const auto robot = station.sourceRobot();
  if (!station.isStation() || !robot) return std::nullopt;
  return std::make_pair(*robot, NodeId(station.category(), station.index()));
}

const RobotFrontendState* SceneGraphProcessor::robot(RobotId robot) const {
  const auto it = robots_.find(robot);
  return it == robots_.end() ? nullptr : &it->second.state;
}

const UpdateSequencer* SceneGraphProcessor::order(RobotId robot) const {
  const auto it = robots_.find(robot);
  return it == robots_.end() ? nullptr : &it->second.order;
}

std::vector<RobotId> SceneGraphProcessor::robotsWithData() const {
  std::vector<RobotId> robots;
  for (const auto& [robot, slot] : robots_) {
    if (slot.order.counts().appliedTotal() > 0) robots.push_back(robot);
  }
  return robots;
}

UpdateCounts SceneGraphProcessor::counts() const {
  UpdateCounts counts;
  for (const auto& [robot, slot] : robots_) counts += slot.order.counts();
  counts.offered += refused_without_robot_;
  counts.rejected += refused_without_robot_;
  return counts;
}

std::vector<RobotId> SceneGraphProcessor::robots() const {
  std::vector<RobotId> robots;
  for (const auto& [robot, slot] : robots_) robots.push_back(robot);
  return robots;
}

std::optional<RobotId> SceneGraphProcessor::frameOf(NodeId station) const {
  const auto source = station.sourceRobot();
  if (!source || !graph_.hasNode(station)) return std::nullopt;
  const RobotFrontendState* state = robot(*source);
  return state ? std::optional<RobotId>(state->frame) : std::nullopt;
}

UpdateReport SceneGraphProcessor::finish(UpdateReport report) const {
  if (report.outcome != UpdateOutcome::kApplied && log_) {
    log_("robot " + report.robot.str() + " update " + std::to_string(report.sequence) + ": " +
         updateOutcomeName(report.outcome) + ": " + report.message);
  }
  return report;
}

UpdateReport SceneGraphProcessor::process(const RobotUpdate& update) {
  UpdateReport report;
  report.robot = update.robot;
  report.sequence = update.sequence;
  if (Status valid = validateRobotUpdate(update); !valid) {
    report.message = valid.message();
    if (update.robot.isValid())
      slot(update.robot).order.refuse();
    else
      ++refused_without_robot_;
    return finish(report);
  }
  RobotSlot& robot = slot(update.robot);  // a robot joins with its first update
  const SequencedUpdate sequenced =
      robot.order.offer(update, [&](const RobotUpdate& u) { return apply(robot, u, report); });
  report.outcome = sequenced.outcome;
  report.message = sequenced.message;
  report.applied = sequenced.applied;
  if (log_) {
    for (const std::string& rejection : sequenced.released_rejections)
      log_("robot " + update.robot.str() + " buffered update " + rejection +
           "; the robot now waits for a snapshot");
  }
  return finish(report);
}

SceneGraphProcessor::RobotSlot& SceneGraphProcessor::slot(RobotId robot) {
  auto it = robots_.find(robot);
  if (it == robots_.end()) {
    it = robots_
             .emplace(robot, RobotSlot{RobotFrontendState{},
                                       UpdateSequencer(options_, io::robotUpdateDigest)})
             .first;
    it->second.state.frame = robot;
  }
  return it->second;
}

Status SceneGraphProcessor::apply(RobotSlot& slot, const RobotUpdate& update,
                                  UpdateReport& report) {
  RobotFrontendState& state = slot.state;
  const RobotId robot = update.robot;
  const std::string at = where(update);
  const bool snapshot = update.is_snapshot;
  const auto station = [&](NodeId id) -> Result<NodeId> {
    const auto mapped = toStation(robot, id);
    if (!mapped) return Error{at + ": node id " + id.str() + " is not a robot-side id"};
    return *mapped;
  };

  // The graph delta in station ids.
  GraphDelta delta;
  std::set<NodeId> removed, added;
  std::vector<NodeId> new_keyframes;  // reported only once the update applied
  if (snapshot) {
    for (const NodeId id : graph_.nodesOfRobot(robot)) {
      delta.removed_nodes.push_back(id);
      removed.insert(id);
    }
  }
  for (const NodeId id : update.graph.removed_nodes) {
    auto mapped = station(id);
    if (!mapped) return Error{mapped.error()};
    if (!graph_.hasNode(mapped.value()) && !snapshot)
      return Error{at + ": removes " + id.str() + ", which the robot never sent"};
    if (removed.insert(mapped.value()).second) delta.removed_nodes.push_back(mapped.value());
  }
  for (const Node& original : update.graph.nodes) {
    if (original.layer() == Layer::kAgents && original.id.category() != robot.prefix())
      return Error{at + ": agent node " + original.id.str() + " does not carry robot " +
                   robot.str() + "'s prefix"};
    auto mapped = station(original.id);
    if (!mapped) return Error{mapped.error()};
    Node node = original;
    node.id = mapped.value();
    added.insert(node.id);
    if (node.layer() == Layer::kAgents && !graph_.hasNode(node.id))
      new_keyframes.push_back(node.id);
    delta.nodes.push_back(std::move(node));
  }
  for (const EdgeKey& key : update.graph.removed_edges) {
    auto a = station(key.first()), b = station(key.second());
    if (!a || !b) return Error{!a ? a.error() : b.error()};
    delta.removed_edges.emplace_back(a.value(), b.value());
  }
  for (const Edge& edge : update.graph.edges) {
    auto a = station(edge.source), b = station(edge.target);
    if (!a || !b) return Error{!a ? a.error() : b.error()};
    delta.edges.push_back({a.value(), b.value(), edge.info});
  }
  // The station graph holds no mesh: each robot's mesh is kept beside it.
  delta.mesh.vertex_start = graph_.mesh().vertices.size();
  delta.mesh.face_start = graph_.mesh().faces.size();

  const auto existsAfter = [&](NodeId id) {
    return added.count(id) || (graph_.hasNode(id) && !removed.count(id));
  };
  // The robot's mesh delta must fit its mesh.
  const MeshDelta& mesh = update.graph.mesh;
  const size_t vertices = snapshot ? 0 : state.mesh.vertices.size();
  const size_t faces = snapshot ? 0 : state.mesh.faces.size();
  if (mesh.vertex_start > vertices || mesh.face_start > faces)
    return Error{at + ": mesh starts at vertex " + std::to_string(mesh.vertex_start) + ", face " +
                 std::to_string(mesh.face_start) + " but the robot's mesh has " +
                 std::to_string(vertices) + " vertices, " + std::to_string(faces) + " faces"};
  const uint64_t vertex_count = mesh.vertex_start + mesh.vertices.size();
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    for (const uint32_t v : mesh.faces[f]) {
      if (v >= vertex_count)
        return Error{at + ": mesh face " + std::to_string(mesh.face_start + f) + " uses vertex " +
                     std::to_string(v) + " of " + std::to_string(vertex_count)};
    }
  }
  // Pose graph, deformation graph and descriptors refer to this robot's keyframes.
  std::vector<PoseGraphEdge> pose_graph;
  for (const PoseGraphEdge& e : update.pose_graph) {
    auto from = station(e.from), to = station(e.to);
    if (!from || !to) return Error{!from ? from.error() : to.error()};
    if (e.from.category() != robot.prefix() || e.to.category() != robot.prefix() ||
        !existsAfter(from.value()) || !existsAfter(to.value()))
      return Error{at + ": pose-graph edge " + e.from.str() + " - " + e.to.str() +
                   " is not between keyframes the robot sent"};
    PoseGraphEdge mapped = e;
    mapped.from = from.value();
    mapped.to = to.value();
    pose_graph.push_back(mapped);
  }
  std::vector<ControlPoint> points;
  for (const ControlPoint& p : update.deformation.points) {
    auto keyframe = station(p.keyframe);
    if (!keyframe || !existsAfter(keyframe.value()))
      return Error{at + ": control point " + std::to_string(p.id) + " is attached to " +
                   p.keyframe.str() + ", which the robot never sent"};
    ControlPoint mapped = p;
    mapped.keyframe = keyframe.value();
    points.push_back(mapped);
  }
  std::vector<KeyframeDescriptor> descriptors;
  for (const KeyframeDescriptor& d : update.descriptors) {
    auto keyframe = station(d.keyframe);
    if (!keyframe || !existsAfter(keyframe.value()))
      return Error{at + ": descriptor of " + d.keyframe.str() + ", which the robot never sent"};
    KeyframeDescriptor mapped = d;
    mapped.keyframe = keyframe.value();
    descriptors.push_back(std::move(mapped));
  }

  // All checked but what applyDelta checks itself; it changes nothing when it fails. The nodes
  // it removes or changes leave the indexes first, and those it leaves or makes come back.
  std::set<NodeId> touched = removed;
  touched.insert(added.begin(), added.end());
  const auto reindex = [&](int sign) {
    for (const NodeId id : touched) index(id, sign);
  };
  reindex(-1);
  if (Status status = applyDelta(graph_, delta); !status) {
    reindex(+1);
    return Error{at + ": " + status.message()};
  }
  reindex(+1);

  RobotStateDelta changed;
  changed.robot = robot;
  changed.snapshot = snapshot;
  changed.mesh = mesh;
  changed.pose_graph = std::move(pose_graph);
  changed.control_points = std::move(points);
  changed.control_point_edges = update.deformation.edges;
  changed.time_ns = update.time_ns;
  changed.provided_layers = update.provided_layers;
  applyStateDelta(state, changed);
  if (snapshot) state.descriptors.clear();
  for (KeyframeDescriptor& d : descriptors) state.descriptors[d.keyframe] = std::move(d);
  // Descriptors of keyframes gone (a snapshot removes and re-sends the robot's nodes: only those it
  // does not re-send are gone).
  for (const NodeId id : removed)
    if (!added.count(id)) state.descriptors.erase(id);
  report.new_keyframes.insert(report.new_keyframes.end(), new_keyframes.begin(),
                              new_keyframes.end());
  report.nodes_changed += delta.nodes.size();
  report.nodes_removed += delta.removed_nodes.size();
  if (keep_deltas_) deltas_.push_back({std::move(delta), std::move(changed)});
  return Status::Ok();
}

void SceneGraphProcessor::index(NodeId id, int sign) {
  const Node* node = graph_.findNode(id);
  if (node == nullptr) return;
  if (node->layer() == Layer::kObjects) {
    const uint32_t label = node->semantic()->label;
    if (sign > 0) {
      ++objects_per_label_[label];
    } else if (--objects_per_label_[label] == 0) {
      objects_per_label_.erase(label);
    }
  }
  const auto* agent = node->find<AgentAttributes>();
  const auto robot = node->robot();
  if (agent == nullptr || !robot) return;
  auto& by_time = keyframe_times_[*robot];
  if (sign > 0) {
    by_time[agent->timestamp_ns].insert(id);
    return;
  }
  const auto at = by_time.find(agent->timestamp_ns);
  at->second.erase(id);
  if (at->second.empty()) by_time.erase(at);
}

std::optional<NodeId> SceneGraphProcessor::keyframeNearest(RobotId robot, int64_t time_ns) const {
  const auto of_robot = keyframe_times_.find(robot);
  if (of_robot == keyframe_times_.end() || of_robot->second.empty()) return std::nullopt;
  const auto& by_time = of_robot->second;
  // The first stamp at or after time_ns, and the last before it: the nearest is one of them.
  const auto after = by_time.lower_bound(time_ns);
  std::optional<std::pair<int64_t, NodeId>> best;  // (gap, id)
  const auto consider = [&](const auto& entry) {
    const std::pair<int64_t, NodeId> candidate{std::llabs(entry.first - time_ns),
                                               *entry.second.begin()};
    if (!best || candidate < *best) best = candidate;
  };
  if (after != by_time.end()) consider(*after);
  if (after != by_time.begin()) consider(*std::prev(after));
  return best->second;
}

void applyStateDelta(RobotFrontendState& state, const RobotStateDelta& delta) {
  if (delta.snapshot) {
    state.mesh = Mesh();
    state.pose_graph.clear();
    state.control_points.clear();
    state.control_point_edges.clear();
  }
  const MeshDelta& mesh = delta.mesh;
  state.mesh.vertices.resize(mesh.vertex_start);
  state.mesh.vertices.insert(state.mesh.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
  state.mesh.faces.resize(mesh.face_start);
  state.mesh.faces.insert(state.mesh.faces.end(), mesh.faces.begin(), mesh.faces.end());
  state.pose_graph.insert(state.pose_graph.end(), delta.pose_graph.begin(), delta.pose_graph.end());
  state.control_points.insert(state.control_points.end(), delta.control_points.begin(),
                              delta.control_points.end());
  state.control_point_edges.insert(state.control_point_edges.end(),
                                   delta.control_point_edges.begin(),
                                   delta.control_point_edges.end());
  state.last_time_ns = delta.time_ns;
  state.provided_layers = delta.provided_layers;
}

}  // namespace hydra_multi
