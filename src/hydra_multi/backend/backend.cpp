#include "hydra_multi/backend/backend.h"

#include <chrono>
#include <limits>
#include <set>

#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {
namespace {

// Where a solve of `graph` put the aligned robots' places and objects: places as solved, objects
// moved as their robot's nearest keyframe of about their time (madeAtNs) moved (`motion`: that
// rigid motion, global frame).
struct SolvedNodes {
  std::map<NodeId, Eigen::Vector3d> positions;
  std::map<NodeId, Eigen::Isometry3d> motion;
};
SolvedNodes solvedNodes(const SceneGraph& frontend,
                        const std::vector<RobotDeformationInput>& robots,
                        const DeformationGraph& graph, const DeformationResult& solved,
                        double window_s) {
  SolvedNodes nodes;
  auto& positions = nodes.positions;
  for (const RobotDeformationInput& input : robots) {
    const RobotId robot = input.robot;
    const Eigen::Isometry3d& T = input.T_global_robot;
    std::vector<Eigen::Vector3d> keyframe_positions;
    std::vector<int64_t> keyframe_times;
    std::vector<Eigen::Isometry3d> motion;  // optimized * initial^-1, per keyframe
    std::vector<NodeId> objects;
    for (const NodeId id : frontend.nodesOfRobot(robot)) {
      const Layer layer = frontend.getNode(id).layer();
      const auto solved_pose = solved.poses.find(id);
      if (layer == Layer::kAgents && solved_pose != solved.poses.end()) {
        keyframe_positions.push_back(graph.initial.at(id).translation());
        keyframe_times.push_back(frontend.getNode(id).find<AgentAttributes>()->timestamp_ns);
        motion.push_back(solved_pose->second * graph.initial.at(id).inverse());
      } else if (layer == Layer::kPlaces && solved_pose != solved.poses.end()) {
        positions[id] = solved_pose->second.translation();
      } else if (layer == Layer::kObjects) {
        objects.push_back(id);
      }
    }
    if (keyframe_positions.empty()) continue;
    const TimedNeighbors near(keyframe_positions, keyframe_times, windowNs(window_s));
    for (const NodeId id : objects) {
      const Node& object = frontend.getNode(id);
      const Eigen::Vector3d aligned = T * object.position;
      const Eigen::Isometry3d& moved =
          motion[near.nearest(aligned, madeAtNs(object, input.mesh)).front().index];
      positions[id] = moved * aligned;
      nodes.motion[id] = moved;
    }
  }
  return nodes;
}

bool sameTransform(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff() < 1e-9;
}

}  // namespace

MergeSideFinder::MergeSideFinder(const SceneGraph& frontend, RobotId robot, const Mesh* mesh,
                                 double window_s)
    : frontend_(frontend), robot_(robot), mesh_(mesh) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int64_t> times;
  for (const NodeId id : frontend.nodesOfRobot(robot)) {
    const Node& node = frontend.getNode(id);
    if (node.layer() != Layer::kAgents || node.find<AgentAttributes>() == nullptr) continue;
    keyframes_.push_back(&node);
    positions.push_back(node.position);
    times.push_back(node.find<AgentAttributes>()->timestamp_ns);
  }
  near_ = std::make_unique<TimedNeighbors>(positions, times, windowNs(window_s));
}

AcceptedMerge::Side MergeSideFinder::side(NodeId id) const {
  AcceptedMerge::Side s;
  s.robot = robot_;
  const Node* node = frontend_.findNode(id);
  if (node == nullptr) return s;
  s.position = node->position;
  const auto nearest = near_->nearest(s.position, madeAtNs(*node, mesh_));
  if (nearest.empty()) return s;
  const Node& keyframe = *keyframes_[nearest.front().index];
  s.keyframe_stamp_ns = keyframe.find<AgentAttributes>()->timestamp_ns;
  s.T_robot_keyframe = nodePose(keyframe);
  return s;
}

void Backend::rememberForNextRound(const SceneGraph& frontend, const DeformationGraph& graph,
                                   const DeformationResult& result,
                                   const std::vector<PoseGraphEdge>& merges,
                                   const std::map<RobotId, Eigen::Isometry3d>& T_global_robot) {
  corrections_.clear();
  latest_corrections_.clear();
  last_verdicts_.clear();
  last_alignment_ = T_global_robot;
  if (!options_.incremental) return;
  for (const auto& [id, pose] : result.poses) {
    const auto initial = graph.initial.find(id);
    if (initial != graph.initial.end()) corrections_[id] = pose * initial->second.inverse();
  }
  for (const auto& [robot, T] : T_global_robot) {
    int64_t latest = std::numeric_limits<int64_t>::min();
    for (const NodeId id : frontend.nodesOfRobot(robot)) {
      const AgentAttributes* agent = frontend.getNode(id).find<AgentAttributes>();
      const auto correction = corrections_.find(id);
      if (agent == nullptr || correction == corrections_.end() || agent->timestamp_ns < latest)
        continue;
      latest = agent->timestamp_ns;
      latest_corrections_[robot] = correction->second;
    }
  }
  std::set<std::pair<NodeId, NodeId>> merge_factors;
  for (const PoseGraphEdge& e : merges) merge_factors.insert({e.from, e.to});
  for (const auto& [edge, inlier] : result.robust_inlier) {
    if (!merge_factors.count(edge)) last_verdicts_[edge] = inlier;
  }
}

BackendRoundReport Backend::round(const SceneGraph& frontend,
                                  const std::vector<BackendRobot>& robots,
                                  const std::vector<PoseGraphEdge>& inter_robot, RobotId root,
                                  const std::vector<double>& support) {
  const auto start = std::chrono::steady_clock::now();
  auto lap_start = start;
  const auto lap = [&lap_start] {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - lap_start).count();
    lap_start = now;
    return s;
  };
  BackendRoundReport report;
  report.robots = robots.size();
  report.inter_robot_loop_closures = inter_robot.size();

  // 1. Alignment: estimated, or given, or (ablation) none.
  if (!options_.given_alignment.empty()) {
    for (const BackendRobot& robot : robots) {
      const auto given = options_.given_alignment.find(robot.robot);
      if (given != options_.given_alignment.end())
        aligned_[robot.robot].T_global_robot = given->second;
    }
  } else if (!options_.initial_alignment) {
    for (const BackendRobot& robot : robots) aligned_[robot.robot];
  } else {
    aligned_ = alignment_.update(frontend, inter_robot, root, optimized_first_keyframes_, support);
  }
  const auto& aligned = aligned_;
  report.robots_aligned = aligned.size();
  report.alignment_s = lap();

  // 2. Deformation graph of the aligned robots.
  std::vector<RobotDeformationInput> inputs;
  std::vector<const BackendRobot*> included;
  for (const BackendRobot& robot : robots) {
    const auto it = aligned.find(robot.robot);
    if (it == aligned.end()) continue;
    inputs.push_back({robot.robot, it->second.T_global_robot, robot.pose_graph,
                      robot.control_points, robot.control_point_edges, robot.mesh});
    included.push_back(&robot);
  }
  std::map<RobotId, Eigen::Isometry3d> T_global_robot;
  for (const RobotDeformationInput& input : inputs)
    T_global_robot[input.robot] = input.T_global_robot;
  std::map<RobotId, const Mesh*> meshes;
  for (const BackendRobot* robot : included) meshes[robot->robot] = robot->mesh;
  const bool joint = options_.joint_optimization;
  const std::vector<PoseGraphEdge> loop_closures =
      joint ? inter_robot : std::vector<PoseGraphEdge>();
  // Inter-robot loop closures the alignment's consensus rejected start out of GNC (taken back
  // if they fit its result): GNC alone follows a majority of consistent wrong ones (dorm-2).
  std::set<std::pair<NodeId, NodeId>> held_out;
  if (options_.hold_out_alignment_outliers && options_.initial_alignment &&
      options_.given_alignment.empty()) {
    for (const auto& [edge, inlier] : alignment_.edgeInliers()) {
      if (!inlier) held_out.insert(edge);
    }
  }
  // Reconciliation proposals, on the map the loop closures alone optimize (the skeleton's
  // solve): drift no longer separates two robots' copies of a place there.
  // Incremental rounds: where the last round left the robots whose alignment it shares.
  const auto lastRound = [&](const DeformationGraph& graph) {
    DeformationWarmStart warm;
    if (!options_.incremental) return warm;
    std::set<RobotId> kept;
    for (const auto& [robot, T] : T_global_robot) {
      const auto last = last_alignment_.find(robot);
      if (last != last_alignment_.end() && sameTransform(last->second, T)) kept.insert(robot);
    }
    const auto ofKept = [&kept](NodeId id) {
      const auto robot = id.sourceRobot();
      return robot && kept.count(*robot) != 0;
    };
    for (const auto& [id, initial] : graph.skeleton.poses) {
      if (!ofKept(id)) continue;
      const auto own = corrections_.find(id);
      if (own != corrections_.end()) {
        warm.poses[id] = own->second * initial;
      } else if (const auto latest = latest_corrections_.find(*id.sourceRobot());
                 latest != latest_corrections_.end()) {
        warm.poses[id] = latest->second * initial;
      }
    }
    for (const auto& [edge, inlier] : last_verdicts_) {
      if (ofKept(edge.first) && ofKept(edge.second)) warm.verdicts[edge] = inlier;
    }
    report.loop_closures_known = warm.verdicts.size();
    return warm;
  };
  std::vector<MergeCandidate> candidates;
  DeformationWarmStart after_loop_closures;
  if (options_.reconcile && joint) {
    const DeformationGraph first =
        buildDeformationGraph(frontend, inputs, loop_closures, {}, options_.deformation);
    DeformationGraphOptions skeleton = options_.deformation;
    skeleton.final_iterations = 0;
    const DeformationWarmStart warm = lastRound(first);
    const DeformationResult solved = optimizeDeformationGraph(first, skeleton, held_out, &warm);
    report.loop_closures_redecided += solved.solve.known_contradicted;
    report.solves += solved.solve.solves;
    after_loop_closures.poses = solved.poses;
    if (options_.incremental) after_loop_closures.verdicts = solved.robust_inlier;
    const SolvedNodes nodes =
        solvedNodes(frontend, inputs, first, solved, options_.deformation.link_max_dt_s);
    candidates = refineObjectMerges(
        proposeMerges(frontend, T_global_robot, options_.reconciliation, &nodes.positions),
        frontend, T_global_robot, meshes, options_.reconciliation, &nodes.motion);
  }
  const std::vector<PoseGraphEdge> merges =
      mergeFactors(candidates, T_global_robot, options_.reconciliation);
  const DeformationGraph dg =
      buildDeformationGraph(frontend, inputs, loop_closures, merges, options_.deformation);
  report.variables = dg.initial.size();
  report.factors = dg.graph.edges.size();
  report.build_s = lap();
  // Merge factors start held out too: proposed from the map itself, they are no evidence of their
  // own, and look-alike rooms make wrong ones that would bend the graph (dorm-2: ATE 3.9 m with
  // them in GNC, 1.0 m without); they are kept where they fit the loop closures' result.
  if (options_.hold_out_merges) {
    for (const PoseGraphEdge& e : merges) held_out.insert({e.from, e.to});
  }
  const DeformationWarmStart warm =
      after_loop_closures.poses.empty() ? lastRound(dg) : after_loop_closures;
  const DeformationResult result = optimizeDeformationGraph(dg, options_.deformation, held_out,
                                                            warm.poses.empty() ? nullptr : &warm);
  report.loop_closures_redecided += result.solve.known_contradicted;
  report.solves += result.solve.solves + (result.whole_graph_s > 0.0 ? 1 : 0);
  report.whole_graph_s = result.whole_graph_s;
  report.gnc_s = lap() - result.whole_graph_s;
  inliers_.clear();
  for (const PoseGraphEdge& e : inter_robot) {
    const auto it = result.robust_inlier.find({e.from, e.to});
    if (it == result.robust_inlier.end()) continue;
    inliers_[{e.from, e.to}] = it->second;
    report.inter_robot_inliers += it->second;
  }
  verdicts_.clear();
  for (const BackendRobot* robot : included) {
    if (robot->pose_graph == nullptr) continue;
    for (const PoseGraphEdge& e : *robot->pose_graph) {
      if (e.kind != PoseGraphEdge::Kind::kLoopClosure) continue;
      const auto it = result.robust_inlier.find({e.from, e.to});
      if (it != result.robust_inlier.end()) verdicts_.push_back({e.from, e.to, false, it->second});
    }
  }
  for (const auto& [edge, kept] : inliers_)
    verdicts_.push_back({edge.first, edge.second, true, kept});
  rememberForNextRound(frontend, dg, result, merges, T_global_robot);

  // 3. The backend graph.
  SceneGraph graph;
  optimized_first_keyframes_.clear();
  for (size_t r = 0; r < included.size(); ++r) {
    const BackendRobot& robot = *included[r];
    const Eigen::Isometry3d& T = inputs[r].T_global_robot;
    // Control points before and after, for the mesh and for objects without vertices.
    std::vector<Eigen::Isometry3d> cp_initial, cp_optimized;
    std::vector<int64_t> cp_times;
    if (robot.control_points != nullptr) {
      for (const ControlPoint& cp : *robot.control_points) {
        const NodeId id = controlPointId(robot.robot, cp.id);
        const auto a = dg.initial.find(id);
        const auto b = result.poses.find(id);
        if (a == dg.initial.end() || b == result.poses.end()) continue;
        cp_initial.push_back(a->second);
        cp_optimized.push_back(b->second);
        cp_times.push_back(cp.time_ns);
      }
    }
    // The mesh: aligned, then deformed.
    std::vector<MeshVertex> before, after;
    if (robot.mesh != nullptr) {
      for (MeshVertex v : robot.mesh->vertices) {
        v.position = (T * v.position.cast<double>()).cast<float>();
        before.push_back(v);
      }
      after = before;
      deformMesh(after, cp_initial, cp_optimized, cp_times, options_.deformation.link_max_dt_s,
                 options_.mesh_neighbours);
    }
    std::vector<Eigen::Vector3d> cp_centres;
    for (const Eigen::Isometry3d& c : cp_initial) cp_centres.push_back(c.translation());
    const TimedNeighbors near_cp(cp_centres, cp_times,
                                 windowNs(options_.deformation.link_max_dt_s));
    const uint64_t vertex_offset = graph.mesh().vertices.size();
    int64_t first_time = std::numeric_limits<int64_t>::max();
    for (const NodeId id : frontend.nodesOfRobot(robot.robot)) {
      Node node = frontend.getNode(id);
      if (node.layer() == Layer::kAgents || node.layer() == Layer::kPlaces) {
        const auto pose = result.poses.find(id);
        if (pose == result.poses.end()) continue;
        node.position = pose->second.translation();
        if (AgentAttributes* agent = node.find<AgentAttributes>()) {
          agent->orientation = Eigen::Quaterniond(pose->second.linear()).normalized();
          if (agent->timestamp_ns < first_time) {
            first_time = agent->timestamp_ns;
            optimized_first_keyframes_[robot.robot] = pose->second;
          }
        }
      } else if (ObjectAttributes* object = node.find<ObjectAttributes>()) {
        // Moved as its mesh vertices moved, or as its nearest control point moved.
        const Eigen::Vector3d aligned_position = T * node.position;
        Eigen::Vector3d shift = Eigen::Vector3d::Zero();
        size_t counted = 0;
        for (const uint64_t v : object->mesh_vertices) {
          if (v >= before.size()) continue;
          shift += (after[v].position - before[v].position).cast<double>();
          ++counted;
        }
        if (counted > 0) {
          shift /= double(counted);
        } else if (!cp_centres.empty()) {
          const size_t c =
              near_cp.nearest(aligned_position, node.last_update_time_ns).front().index;
          shift = cp_optimized[c] * (cp_initial[c].inverse() * aligned_position) - aligned_position;
        }
        node.position = aligned_position + shift;
        if (object->semantic.bounding_box) {
          const Eigen::Vector3d half =
              0.5 * (object->semantic.bounding_box->max - object->semantic.bounding_box->min);
          object->semantic.bounding_box = BoundingBox{node.position - half, node.position + half};
        }
        for (uint64_t& v : object->mesh_vertices) v += vertex_offset;
      } else {
        continue;  // rooms and buildings are the backend's own
      }
      graph.addOrUpdateNode(std::move(node));
    }
    for (const MeshVertex& v : after) graph.mesh().vertices.push_back(v);
    if (robot.mesh != nullptr) {
      for (MeshFace f : robot.mesh->faces) {
        for (uint32_t& i : f) i += static_cast<uint32_t>(vertex_offset);
        graph.mesh().faces.push_back(f);
      }
    }
  }
  for (const auto& [key, info] : frontend.edges()) {
    if (graph.hasNode(key.first()) && graph.hasNode(key.second()))
      graph.addOrUpdateEdge(key.first(), key.second(), info);
  }

  // 4. Merges GNC kept, unless fewer than min_valid_share of the proposed ones were kept.
  merges_.clear();
  std::vector<const MergeCandidate*> kept;
  for (const MergeCandidate& c : candidates) {
    const auto it = result.robust_inlier.find({c.target, c.source});
    if (it != result.robust_inlier.end() && it->second) kept.push_back(&c);
  }
  report.merges_proposed = candidates.size();
  if (!candidates.empty() &&
      double(kept.size()) >= options_.reconciliation.min_valid_share * double(candidates.size())) {
    std::map<RobotId, MergeSideFinder> sides;
    const auto side = [&](NodeId id) {
      const RobotId robot = id.sourceRobot().value_or(RobotId(0));
      const auto mesh = meshes.find(robot);
      const auto it =
          sides
              .try_emplace(robot, frontend, robot, mesh == meshes.end() ? nullptr : mesh->second,
                           options_.deformation.link_max_dt_s)
              .first;
      return it->second.side(id);
    };
    // The robots whose copies each merged object unites, for the label votes.
    std::map<NodeId, std::set<RobotId>> voters;
    for (const MergeCandidate* c : kept) {
      if (!graph.hasNode(c->target) || !graph.hasNode(c->source)) continue;
      merges_.push_back({c->target, c->source, c->layer, side(c->target), side(c->source),
                         graph.getNode(c->target).position, graph.getNode(c->source).position});
      graph.mergeNodes(c->target, c->source);
      ++report.merges_accepted;
      if (c->layer != Layer::kObjects) continue;
      for (const NodeId id : {c->target, c->source}) {
        if (const auto robot = id.sourceRobot()) voters[c->target].insert(*robot);
      }
    }
    if (options_.reconciliation.label_votes) {
      for (const LabelDispute& d : resolveLabelDisputes(graph, voters, options_.reconciliation)) {
        merges_.push_back({d.winner, d.loser, Layer::kObjects, side(d.winner), side(d.loser),
                           graph.getNode(d.winner).position, graph.getNode(d.loser).position});
        graph.mergeNodes(d.winner, d.loser);
        ++report.label_merges;
      }
    }
  } else {
    report.merges_undone = kept.size();
  }

  report.graph_s = lap();

  // 5. Rooms.
  if (options_.segment_rooms) {
    const RoomSegmentation rooms = segmentRooms(graph, options_.rooms);
    applyRooms(graph, rooms);
    report.rooms = rooms.rooms.size();
  }
  report.rooms_s = lap();
  graph_ = std::move(graph);
  report.nodes = graph_.numNodes();
  report.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace hydra_multi
