#include "hydra_multi/backend/backend.h"

#include <algorithm>
#include <chrono>
#include <future>
#include <iterator>
#include <optional>
#include <set>

#include "hydra_multi/core/ascending_lookup.h"
#include "hydra_multi/core/background_task.h"
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
    for (const Node* node : frontend.robotNodes(robot)) {
      const NodeId id = node->id;
      const Layer layer = node->layer();
      const auto solved_pose = solved.poses.find(id);
      if (layer == Layer::kAgents && solved_pose != solved.poses.end()) {
        keyframe_positions.push_back(graph.initial.at(id).translation());
        keyframe_times.push_back(node->find<AgentAttributes>()->timestamp_ns);
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

using PoseLookup = AscendingLookup<std::map<NodeId, Eigen::Isometry3d>>;

// Whether `poses` holds a pose for every node of `initial`.
bool posedEverywhere(const std::map<NodeId, Eigen::Isometry3d>& poses,
                     const std::map<NodeId, Eigen::Isometry3d>& initial) {
  return std::includes(poses.begin(), poses.end(), initial.begin(), initial.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
}

}  // namespace

void Backend::align(const SceneGraph& frontend, const std::vector<BackendRobot>& robots,
                    const std::vector<PoseGraphEdge>& inter_robot, RobotId root,
                    const std::vector<double>& support) {
  if (!options_.given_alignment.empty()) {
    for (const BackendRobot& robot : robots) {
      const auto given = options_.given_alignment.find(robot.robot);
      if (given != options_.given_alignment.end())
        aligned_[robot.robot].T_global_robot = given->second;
    }
  } else if (!options_.initial_alignment) {
    for (const BackendRobot& robot : robots) aligned_[robot.robot];
  } else {
    aligned_ = alignment_.update(frontend, inter_robot, root, optimized_first_keyframes_, support,
                                 from_scratch_, &inliers_);
  }
}

Backend::Team Backend::alignedTeam(const std::vector<BackendRobot>& robots) const {
  Team team;
  for (const BackendRobot& robot : robots) {
    const auto it = aligned_.find(robot.robot);
    if (it == aligned_.end()) continue;
    const std::vector<ControlPoint>* points = robot.control_points;
    const std::vector<ControlPointEdge>* edges = robot.control_point_edges;
    if (options_.deformation.control_point_voxel > 0.0 && points != nullptr && edges != nullptr) {
      const ControlPointGraph& coarse = team.coarse[robot.robot] =
          coarserControlPoints(*points, *edges, options_.deformation.control_point_voxel);
      points = &coarse.points;
      edges = &coarse.edges;
    }
    team.inputs.push_back(
        {robot.robot, it->second.T_global_robot, robot.pose_graph, points, edges, robot.mesh});
    team.T_global_robot[robot.robot] = it->second.T_global_robot;
    team.meshes[robot.robot] = robot.mesh;
  }
  return team;
}

std::set<std::pair<NodeId, NodeId>> Backend::alignmentOutliers() const {
  std::set<std::pair<NodeId, NodeId>> held_out;
  if (!options_.hold_out_alignment_outliers || !options_.initial_alignment ||
      !options_.given_alignment.empty())
    return held_out;
  for (const auto& [edge, inlier] : alignment_.edgeInliers()) {
    if (!inlier) held_out.insert(edge);
  }
  return held_out;
}

Backend::Proposals Backend::proposeOnLoopClosureSolve(
    const SceneGraph& frontend, const Team& team, const std::vector<PoseGraphEdge>& loop_closures,
    const std::set<std::pair<NodeId, NodeId>>& held_out, BackendRoundReport& report) const {
  Proposals proposals;
  const auto start = std::chrono::steady_clock::now();
  DeformationGraphOptions skeleton = options_.deformation;
  skeleton.final_iterations = 0;
  if (incremental()) skeleton.solver.readmit_unsolved_share = options_.readmit_unsolved_share;
  DeformationGraph graph =
      buildDeformationGraph(frontend, team.inputs, loop_closures, {}, skeleton);
  std::map<NodeId, Eigen::Isometry3d> last_proposal, last_held_out;
  DeformationWarmStart warm = lastRound(graph, team, &last_proposal, &last_held_out);
  // This solve's own optimum; GNC and the first polish from the one without what it re-admitted,
  // the solve after the re-admission moved as it moved then.
  for (const auto& [id, pose] : last_proposal) warm.poses[id] = pose;
  for (const auto& [id, pose] : last_held_out) warm.poses[id] = pose;
  warm.held_out = std::move(last_held_out);
  warm.readmitted = std::move(last_proposal);
  report.verdicts_known = warm.verdicts.size();
  DeformationResult solved = optimizeDeformationGraph(graph, skeleton, held_out, &warm);
  report.verdicts_redecided += solved.solve.known_contradicted;
  report.solves += solved.solve.solves;
  report.solver_time += solved.solver_time;
  proposals.held_out = solved.solve.held_out_poses;
  proposals.solved.poses = solved.poses;
  proposals.solved.verdicts = solved.robust_inlier;
  const auto solve_end = std::chrono::steady_clock::now();
  report.loop_closure_solve_s = std::chrono::duration<double>(solve_end - start).count();
  const SolvedNodes nodes =
      solvedNodes(frontend, team.inputs, graph, solved, options_.deformation.link_max_dt_s);
  // The objects' candidates and their ICP on a second thread while this one proposes the
  // places'; the places' first, as proposeMerges lists them (ICP passes a place's through).
  std::future<std::vector<MergeCandidate>> objects = std::async(std::launch::async, [&] {
    return refineObjectMerges(proposeMerges(frontend, team.T_global_robot, options_.reconciliation,
                                            &nodes.positions, Layer::kObjects),
                              frontend, team.T_global_robot, team.meshes, options_.reconciliation,
                              &nodes.motion, incremental() ? &icp_cache_ : nullptr);
  });
  proposals.candidates = proposeMerges(frontend, team.T_global_robot, options_.reconciliation,
                                       &nodes.positions, Layer::kPlaces);
  std::vector<MergeCandidate> refined = objects.get();
  proposals.candidates.insert(proposals.candidates.end(), std::make_move_iterator(refined.begin()),
                              std::make_move_iterator(refined.end()));
  report.candidates_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - solve_end).count();
  spent_.keep(std::move(graph));
  spent_.keep(std::move(warm));
  spent_.keep(std::move(solved));
  return proposals;
}

void Backend::recordVerdicts(const Team& team, const std::vector<PoseGraphEdge>& inter_robot,
                             const DeformationResult& result, BackendRoundReport& report) {
  inliers_.clear();
  for (const PoseGraphEdge& e : inter_robot) {
    const auto it = result.robust_inlier.find({e.from, e.to});
    if (it == result.robust_inlier.end()) continue;
    inliers_[{e.from, e.to}] = it->second;
    report.inter_robot_inliers += it->second;
  }
  verdicts_.clear();
  for (const RobotDeformationInput& robot : team.inputs) {
    if (robot.pose_graph == nullptr) continue;
    for (const PoseGraphEdge& e : *robot.pose_graph) {
      if (e.kind != PoseGraphEdge::Kind::kLoopClosure) continue;
      const auto it = result.robust_inlier.find({e.from, e.to});
      if (it != result.robust_inlier.end()) verdicts_.push_back({e.from, e.to, false, it->second});
    }
  }
  for (const auto& [edge, kept] : inliers_)
    verdicts_.push_back({edge.first, edge.second, true, kept});
}

DeformationWarmStart Backend::startWithMerges(const DeformationGraph& graph, const Team& team,
                                              DeformationWarmStart solved,
                                              const std::vector<PoseGraphEdge>& merges,
                                              std::set<std::pair<NodeId, NodeId>>& held_out,
                                              BackendRoundReport& report) const {
  if (solved.poses.empty()) {
    DeformationWarmStart warm = lastRound(graph, team);
    report.verdicts_known = warm.verdicts.size();
    return warm;
  }
  DeformationWarmStart warm = std::move(solved);
  // The loop closures as the solve without merges decided them, those it took back among them
  // (it tested them held out).
  for (const auto& [edge, inlier] : warm.verdicts) {
    if (inlier) held_out.erase(edge);
  }
  if (!incremental()) return warm;
  // The merges as the last round decided them. Poses from the last round's solve with merges,
  // moved as the loop closures' solve moved them since: P_now P_then^-1 S_then.
  std::map<NodeId, Eigen::Isometry3d> last_proposal;
  DeformationWarmStart last = lastRound(graph, team, &last_proposal);
  PoseLookup proposed_then(last_proposal), skeleton_then(last.last_skeleton);
  for (auto& [id, pose] : warm.poses) {
    const Eigen::Isometry3d* then = proposed_then.find(id);
    const Eigen::Isometry3d* skeleton = skeleton_then.find(id);
    if (then != nullptr && skeleton != nullptr) pose = pose * then->inverse() * *skeleton;
  }
  warm.last_whole = std::move(last.last_whole);
  warm.last_skeleton = std::move(last.last_skeleton);
  warm.whole_owed = last.whole_owed;
  for (const PoseGraphEdge& e : merges) {
    const auto verdict = last.verdicts.find({e.from, e.to});
    if (verdict != last.verdicts.end()) {
      warm.verdicts.insert(*verdict);
      if (verdict->second) held_out.erase(verdict->first);  // kept last round: known
    } else if (options_.admit_fitting_merges) {
      warm.admit_if_fitting.insert({e.from, e.to});  // new: known where it fits the start
    }
  }
  return warm;
}

Backend::MapInProgress Backend::startBackendGraph(const SceneGraph& frontend, const Team& team,
                                                  bool spare) const {
  MapInProgress made;
  std::promise<SceneGraph> copy;
  if (spare) made.spare = copy.get_future();
  made.unplaced = startInBackground([&frontend, &team, spare, copy = std::move(copy)]() mutable {
    SceneGraph map = unplacedMap(frontend, team.inputs);
    if (spare) copy.set_value(map);
    return map;
  });
  return made;
}

void Backend::planMergesFor(const SceneGraph& frontend, const Team& team,
                            const std::vector<MergeCandidate>& candidates,
                            const RobustVerdicts& verdicts, MapInProgress& made) const {
  std::vector<bool> kept = keptCandidates(candidates, verdicts);
  if (made.planned.valid()) {
    if (kept == made.planned_kept) return;
    made.planned.wait();  // planned for other verdicts: planned again from the copy, or else
    made.planned = {};    // made anew after placing
    if (!made.spare.valid()) return;
    made.unplaced = std::move(made.spare);
  }
  made.planned_kept = kept;
  ++made.plans;
  made.planned = startInBackground([&, kept = std::move(kept)] {
    SceneGraph map = made.unplaced.get();
    MergePlan plan = planMerges(map, frontend, candidates, kept, team.meshes,
                                options_.deformation.link_max_dt_s, options_.reconciliation);
    return std::make_pair(std::move(map), std::move(plan));
  });
}

SceneGraph Backend::placeBackendGraph(const SceneGraph& frontend, const Team& team,
                                      const DeformationGraph& graph,
                                      const DeformationResult& result,
                                      const std::vector<MergeCandidate>& candidates,
                                      MapInProgress& made, BackendRoundReport& report) {
  if (!incremental()) mesh_bindings_.clear();
  std::map<RobotId, MeshBinding> fresh;
  std::map<RobotId, MeshBinding>& bindings = incremental() ? mesh_bindings_ : fresh;
  // A keyframe or place without a pose leaves the graph before any merge (placeMap), so where one
  // lacks it the merges are made again after (mergeKept).
  SceneGraph map;
  std::optional<MergePlan> plan;
  if (made.planned.valid()) {
    auto [merged_map, planned] = made.planned.get();
    if (posedEverywhere(result.poses, graph.initial)) {
      map = std::move(merged_map);
      plan = std::move(planned);
    } else {
      map = unplacedMap(frontend, team.inputs);
    }
  } else {
    map = made.unplaced.valid() ? made.unplaced.get() : unplacedMap(frontend, team.inputs);
  }
  std::map<NodeId, Placement> placements;
  if (plan) placements = mergedNodes(*plan);
  placeMap(map, frontend, team.inputs, graph, result.poses, options_.deformation,
           options_.mesh_neighbours, &optimized_first_keyframes_, &bindings,
           plan ? &placements : nullptr);
  for (const auto& [robot, binding] : bindings) report.vertices_blended += binding.reblended;
  report.merges_proposed = candidates.size();
  report.merge_plans = made.plans;
  const double window_s = options_.deformation.link_max_dt_s;
  MergeOutcome merged = plan ? placeMerged(map, std::move(*plan), std::move(placements), frontend,
                                           team.meshes, options_.reconciliation, window_s)
                             : mergeKept(map, frontend, candidates, result.robust_inlier,
                                         team.meshes, options_.reconciliation, window_s);
  merges_ = std::move(merged.merges);
  report.merges_accepted = merged.accepted;
  report.merges_undone = merged.undone;
  report.label_merges = merged.label_merges;
  return map;
}

BackendRoundReport Backend::round(const SceneGraph& frontend,
                                  const std::vector<BackendRobot>& robots,
                                  const std::vector<PoseGraphEdge>& inter_robot, RobotId root,
                                  const std::vector<double>& support, bool from_scratch) {
  const auto start = std::chrono::steady_clock::now();
  auto lap_start = start;
  const auto lap = [&lap_start] {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - lap_start).count();
    lap_start = now;
    return s;
  };
  BackendRoundReport report;
  from_scratch_ = from_scratch;
  report.from_scratch = from_scratch || !options_.incremental;
  report.robots = robots.size();
  report.inter_robot_loop_closures = inter_robot.size();

  // 1. Alignment.
  align(frontend, robots, inter_robot, root, support);
  report.robots_aligned = aligned_.size();
  report.alignment_s = lap();

  // 2. Reconciliation proposals on the loop closures' solve, as merge factors; the backend graph
  //    begun meanwhile.
  const Team team = alignedTeam(robots);
  if (incremental())
    report.robots_afresh =
        team.T_global_robot.size() - memory_.alignedAsBefore(team.T_global_robot).size();
  const bool joint = options_.joint_optimization;
  const std::vector<PoseGraphEdge> none;
  const std::vector<PoseGraphEdge>& loop_closures = joint ? inter_robot : none;
  std::set<std::pair<NodeId, NodeId>> held_out = alignmentOutliers();
  Proposals proposals;
  MapInProgress made =  // after `proposals`: its plan reads their candidates
      startBackendGraph(frontend, team, options_.merge_while_solving && options_.plan_merges_ahead);
  if (options_.reconcile && joint)
    proposals = proposeOnLoopClosureSolve(frontend, team, loop_closures, held_out, report);
  const std::vector<PoseGraphEdge> merges =
      mergeFactors(proposals.candidates, team.T_global_robot, options_.reconciliation);
  DeformationGraph graph =
      buildDeformationGraph(frontend, team.inputs, loop_closures, merges, options_.deformation);
  report.variables = graph.initial.size();
  report.factors = graph.graph.edges.size();
  report.build_s = lap();

  // 3. The deformation graph with the merge factors, held out until they fit (in an incremental
  //    round, a new one that fits the start is known instead); the merges planned meanwhile.
  if (options_.hold_out_merges) {
    for (const PoseGraphEdge& e : merges) held_out.insert({e.from, e.to});
  }
  const std::map<NodeId, Eigen::Isometry3d> proposal_poses = proposals.solved.poses;
  DeformationWarmStart warm =
      startWithMerges(graph, team, std::move(proposals.solved), merges, held_out, report);
  using Verdicts = std::function<void(const RobustVerdicts&)>;
  const Verdicts plan = [&](const RobustVerdicts& verdicts) {
    planMergesFor(frontend, team, proposals.candidates, verdicts, made);
  };
  const bool planned = options_.merge_while_solving;
  const bool ahead = planned && options_.plan_merges_ahead;
  DeformationGraphOptions with_merges = options_.deformation;
  if (incremental() && options_.readmit_unsolved_with_merges && with_merges.two_stage &&
      with_merges.final_iterations > 0) {
    with_merges.solver.readmit_unsolved_share = options_.readmit_unsolved_share;
    with_merges.solver.readmit_unsolved_first = true;
  }
  DeformationResult result =
      optimizeDeformationGraph(graph, with_merges, held_out, warm.poses.empty() ? nullptr : &warm,
                               planned ? plan : Verdicts(), ahead ? plan : Verdicts());
  report.verdicts_redecided += result.solve.known_contradicted;
  report.merges_admitted = result.admitted;
  report.solves += result.solve.solves + (result.whole_graph_free > 0 ? 1 : 0);
  report.solver_time += result.solver_time;
  report.whole_graph_s = result.whole_graph_s;
  report.whole_graph_free = result.whole_graph_free;
  report.whole_graph_ahead = result.whole_graph_analyzed_ahead;
  report.gnc_s = lap() - result.whole_graph_s;
  recordVerdicts(team, inter_robot, result, report);
  // What the next round starts from, kept on the second thread while this one makes its graph.
  std::future<void> remembered = startInBackground([&] {
    memory_.remember(frontend, graph, result, proposal_poses, proposals.held_out,
                     team.T_global_robot, options_.incremental);
  });

  // 4. The backend graph, and the merges GNC kept.
  SceneGraph map =
      placeBackendGraph(frontend, team, graph, result, proposals.candidates, made, report);
  report.graph_s = lap();

  // 5. Rooms.
  if (options_.segment_rooms) {
    const RoomSegmentation rooms = segmentRooms(map, options_.rooms);
    applyRooms(map, rooms);
    report.rooms = rooms.rooms.size();
  }
  report.rooms_s = lap();
  remembered.get();
  spent_.keep(std::move(graph_));
  graph_ = std::move(map);
  spent_.keep(std::move(graph));
  spent_.keep(std::move(warm));
  spent_.keep(std::move(result));
  spent_.release();
  report.nodes = graph_.numNodes();
  report.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace hydra_multi
