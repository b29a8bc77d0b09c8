#include "hydra_multi/backend/deformation_graph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <set>
#include <unordered_map>

#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {
namespace {

Eigen::Isometry3d at(const Eigen::Vector3d& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = p;
  return T;
}

PoseGraphEdge edge(NodeId from, NodeId to, const Eigen::Isometry3d& T_from_to, double variance,
                   PoseGraphEdge::Kind kind = PoseGraphEdge::Kind::kOdometry) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = T_from_to;
  e.information = informationFromVariances(variance, variance);
  e.kind = kind;
  return e;
}

// A gauge prior: the weakest of links from the anchor to a robot's first keyframe, so that a
// robot whose every inter-robot factor GNC rejects still has a defined place (as aligned).
constexpr double kGaugeVariance = 1e6;

// The nodes a warm-started whole-graph solve moves (DeformationGraphOptions::local_whole_graph):
// those of the factors whose two poses are placed relative to each other otherwise than in the
// earlier solution (or that it lacks), and those within local_hops edges of them; none without
// an earlier solution.
std::optional<std::set<NodeId>> changedNodes(const PoseGraph& whole,
                                             const std::map<NodeId, Eigen::Isometry3d>& start,
                                             const DeformationWarmStart& warm,
                                             const DeformationGraphOptions& options) {
  if (warm.last_whole.empty()) return std::nullopt;
  std::set<NodeId> changed;
  std::unordered_map<NodeId, std::vector<NodeId>> neighbours;
  for (const PoseGraphEdge& e : whole.edges) {
    if (!start.count(e.from) || !start.count(e.to)) continue;
    neighbours[e.from].push_back(e.to);
    neighbours[e.to].push_back(e.from);
    const auto from_then = warm.last_whole.find(e.from), to_then = warm.last_whole.find(e.to);
    bool moved = from_then == warm.last_whole.end() || to_then == warm.last_whole.end();
    if (!moved) {
      const Eigen::Isometry3d delta = (from_then->second.inverse() * to_then->second).inverse() *
                                      (start.at(e.from).inverse() * start.at(e.to));
      moved = delta.translation().norm() > options.local_move_m ||
              Eigen::AngleAxisd(delta.linear()).angle() > options.local_move_rad;
    }
    if (moved) {
      changed.insert(e.from);
      changed.insert(e.to);
    }
  }
  std::vector<NodeId> frontier(changed.begin(), changed.end());
  for (int hop = 0; hop < options.local_hops && !frontier.empty(); ++hop) {
    std::vector<NodeId> next;
    for (const NodeId id : frontier) {
      for (const NodeId n : neighbours[id]) {
        if (changed.insert(n).second) next.push_back(n);
      }
    }
    frontier = std::move(next);
  }
  return changed;
}

// The held-out factors of `candidates` (from, to) whose squared residual at `poses` is within GNC's
// threshold (both ends placed) become known inliers of `solver`; returns how many.
size_t admitFitting(const PoseGraph& graph, const std::map<NodeId, Eigen::Isometry3d>& poses,
                    NodeId anchor, const std::set<std::pair<NodeId, NodeId>>& candidates,
                    RobustPgoOptions& solver) {
  PoseGraph held;
  std::vector<size_t> index;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (solver.held_out[k] && candidates.count({e.from, e.to}) && poses.count(e.from) &&
        poses.count(e.to)) {
      held.edges.push_back(e);
      index.push_back(k);
    }
  }
  const std::vector<double> r2 =
      PoseGraphProblem(held, poses, anchor, solver.solver).squaredResiduals();
  const double c2 = solver.gnc.thresholdSq();
  size_t admitted = 0;
  for (size_t i = 0; i < index.size(); ++i) {
    if (r2[i] > c2) continue;
    solver.held_out[index[i]] = false;
    solver.known_inlier[index[i]] = true;
    ++admitted;
  }
  return admitted;
}

}  // namespace

NodeId controlPointId(RobotId robot, uint64_t index) { return NodeId::station('M', robot, index); }

int64_t madeAtNs(const Node& node, const Mesh* mesh) {
  const ObjectAttributes* object = node.find<ObjectAttributes>();
  if (object == nullptr || mesh == nullptr) return node.last_update_time_ns;
  std::vector<int64_t> times;
  for (const uint64_t v : object->mesh_vertices) {
    if (v < mesh->vertices.size()) times.push_back(mesh->vertices[v].time_ns);
  }
  if (times.empty()) return node.last_update_time_ns;
  const auto middle = times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2);
  std::nth_element(times.begin(), middle, times.end());
  return *middle;
}

DeformationGraph buildDeformationGraph(const SceneGraph& frontend,
                                       const std::vector<RobotDeformationInput>& robots,
                                       const std::vector<PoseGraphEdge>& inter_robot,
                                       const std::vector<PoseGraphEdge>& merges,
                                       const DeformationGraphOptions& options) {
  DeformationGraph dg;
  std::vector<NodeId> first_keyframes;
  std::set<NodeId> merged;  // objects in merge candidates become nodes too
  std::set<NodeId> control_points;
  for (const PoseGraphEdge& e : merges) {
    merged.insert(e.from);
    merged.insert(e.to);
  }
  // At most: the robots' own edges, a place's (or merged object's) tie, a control point's ties,
  // the frames' ties and the robust factors (large at team scale: no growth by copies).
  size_t skeleton_most = inter_robot.size() + merges.size() + robots.size() + merged.size();
  size_t control_most = 0;
  for (const RobotDeformationInput& input : robots) {
    if (input.pose_graph != nullptr) skeleton_most += input.pose_graph->size();
    if (input.control_points != nullptr) control_most += input.control_points->size();
    if (input.control_point_edges != nullptr) control_most += input.control_point_edges->size();
    skeleton_most += frontend.nodesOfRobot(input.robot, Layer::kPlaces).size();
  }
  dg.graph.edges.reserve(skeleton_most + control_most);
  dg.skeleton.edges.reserve(skeleton_most);
  for (const RobotDeformationInput& input : robots) {
    const Eigen::Isometry3d& T = input.T_global_robot;
    std::map<NodeId, Eigen::Isometry3d> local;  // keyframes in the robot's frame
    std::map<NodeId, int64_t> keyframe_time;
    std::vector<NodeId> places;
    NodeId first;
    int64_t first_time = std::numeric_limits<int64_t>::max();
    for (const NodeId id : frontend.nodesOfRobot(input.robot)) {
      const Node& node = frontend.getNode(id);
      if (node.layer() == Layer::kAgents) {
        local[id] = nodePose(node);
        dg.initial[id] = T * local[id];
        const int64_t t = node.find<AgentAttributes>()->timestamp_ns;
        keyframe_time[id] = t;
        if (t < first_time) {
          first_time = t;
          first = id;
        }
      } else if (node.layer() == Layer::kPlaces ||
                 (node.layer() == Layer::kObjects && merged.count(id))) {
        places.push_back(id);
      }
    }
    if (local.empty()) continue;
    first_keyframes.push_back(first);
    if (input.pose_graph != nullptr) {
      for (PoseGraphEdge e : *input.pose_graph) {
        if (!local.count(e.from) || !local.count(e.to)) continue;
        const bool closure = e.kind == PoseGraphEdge::Kind::kLoopClosure;
        if (!options.use_sent_information) {
          const double variance =
              closure ? options.loop_closure_variance : options.odometry_variance;
          e.information = informationFromVariances(variance, variance);
        }
        if (!closure) {
          e.information.block<3, 3>(0, 3).setZero();
          e.information.block<3, 3>(3, 0).setZero();
          e.information.block<3, 3>(3, 3) =
              Eigen::Matrix3d::Identity() / options.odometry_rotation_variance;
        }
        dg.graph.edges.push_back(e);
        dg.skeleton.edges.push_back(e);
        if (closure) ++dg.robust_factors;
      }
    }
    // Mesh control points, their rigidity and the keyframes that observed them.
    const int64_t window = windowNs(options.link_max_dt_s);
    std::vector<Eigen::Vector3d> cp_positions;
    std::vector<int64_t> cp_times;
    std::vector<NodeId> cp_ids;
    std::map<uint64_t, const ControlPoint*> cp_by_index;
    if (input.control_points != nullptr) {
      for (const ControlPoint& cp : *input.control_points) {
        const NodeId id = controlPointId(input.robot, cp.id);
        dg.initial[id] = T * at(cp.position);
        control_points.insert(id);
        cp_positions.push_back(cp.position);
        cp_times.push_back(cp.time_ns);
        cp_ids.push_back(id);
        cp_by_index[cp.id] = &cp;
        const auto keyframe = local.find(cp.keyframe);
        if (keyframe != local.end()) {
          dg.observed_by[id] = cp.keyframe;
          dg.graph.edges.push_back(edge(cp.keyframe, id,
                                        keyframe->second.inverse() * at(cp.position),
                                        options.mesh_variance));
        }
      }
    }
    if (input.control_point_edges != nullptr) {
      for (const ControlPointEdge& e : *input.control_point_edges) {
        const auto a = cp_by_index.find(e.from), b = cp_by_index.find(e.to);
        if (a == cp_by_index.end() || b == cp_by_index.end()) continue;
        if (window > 0 && std::abs(a->second->time_ns - b->second->time_ns) > window) continue;
        dg.graph.edges.push_back(
            edge(controlPointId(input.robot, e.from), controlPointId(input.robot, e.to),
                 at(b->second->position - a->second->position), options.mesh_variance));
      }
    }
    // Places (and merge-candidate objects): linked to the nearest control point, or else the
    // nearest keyframe, of those the robot made about when it placed the node (madeAtNs).
    const TimedNeighbors near_cp(cp_positions, cp_times, window);
    std::vector<Eigen::Vector3d> kf_positions;
    std::vector<int64_t> kf_times;
    std::vector<NodeId> kf_ids;
    for (const auto& [id, pose] : local) {
      kf_positions.push_back(pose.translation());
      kf_times.push_back(keyframe_time[id]);
      kf_ids.push_back(id);
    }
    const TimedNeighbors near_kf(kf_positions, kf_times, window);
    for (const NodeId place : places) {
      const Node& node = frontend.getNode(place);
      const Eigen::Vector3d p = node.position;
      dg.initial[place] = T * at(p);
      const int64_t made = madeAtNs(node, input.mesh);
      const size_t k = near_kf.nearest(p, made).front().index;
      const PoseGraphEdge to_keyframe =
          edge(kf_ids[k], place, local[kf_ids[k]].inverse() * at(p), options.mesh_variance);
      dg.skeleton.edges.push_back(to_keyframe);
      const auto cp = near_cp.nearest(p, made);
      if (!cp.empty() && cp.front().distance <= options.place_link_radius) {
        dg.graph.edges.push_back(edge(cp_ids[cp.front().index], place,
                                      at(p - cp_positions[cp.front().index]),
                                      options.mesh_variance));
      } else {
        dg.graph.edges.push_back(to_keyframe);
      }
    }
  }
  if (first_keyframes.empty()) return dg;
  dg.anchor = first_keyframes.front();
  for (size_t r = 1; r < first_keyframes.size(); ++r) {
    dg.graph.edges.push_back(edge(dg.anchor, first_keyframes[r],
                                  dg.initial[dg.anchor].inverse() * dg.initial[first_keyframes[r]],
                                  kGaugeVariance));
    dg.skeleton.edges.push_back(dg.graph.edges.back());
  }
  for (const auto* list : {&inter_robot, &merges}) {
    for (PoseGraphEdge e : *list) {
      if (!dg.initial.count(e.from) || !dg.initial.count(e.to)) continue;
      e.kind = PoseGraphEdge::Kind::kLoopClosure;
      if (!options.use_sent_information && list == &inter_robot)
        e.information =
            informationFromVariances(options.loop_closure_variance, options.loop_closure_variance);
      dg.graph.edges.push_back(e);
      dg.skeleton.edges.push_back(e);
      ++dg.robust_factors;
      if (list == &inter_robot) ++dg.inter_robot_factors;
    }
  }
  dg.graph.poses = dg.initial;
  for (const auto& [id, pose] : dg.initial) {
    if (!control_points.count(id)) dg.skeleton.poses[id] = pose;
  }
  return dg;
}

DeformationResult optimizeDeformationGraph(const DeformationGraph& graph,
                                           const DeformationGraphOptions& options,
                                           const std::set<std::pair<NodeId, NodeId>>& held_out,
                                           const DeformationWarmStart* warm) {
  DeformationResult result;
  if (graph.initial.empty()) return result;
  const PoseGraph& robust = options.two_stage ? graph.skeleton : graph.graph;
  RobustPgoOptions solver = options.solver;
  solver.held_out.assign(robust.edges.size(), false);
  if (warm != nullptr) {
    solver.earlier_held_out = warm->held_out;
    solver.earlier_readmitted = warm->readmitted;
  }
  solver.known_inlier.assign(robust.edges.size(), false);
  for (size_t k = 0; k < robust.edges.size(); ++k) {
    const PoseGraphEdge& e = robust.edges[k];
    if (e.kind != PoseGraphEdge::Kind::kLoopClosure) continue;
    std::optional<bool> verdict;
    if (warm != nullptr) {
      const auto it = warm->verdicts.find({e.from, e.to});
      if (it != warm->verdicts.end()) verdict = it->second;
    }
    if (held_out.count({e.from, e.to}) || verdict == false) {
      solver.held_out[k] = true;
    } else if (verdict == true) {
      solver.known_inlier[k] = true;
    }
  }
  std::map<NodeId, Eigen::Isometry3d> initial_poses = robust.poses;
  if (warm != nullptr) {
    std::set<NodeId> unplaced;
    for (auto& [id, pose] : initial_poses) {
      if (const auto it = warm->poses.find(id); it != warm->poses.end()) {
        pose = it->second;
      } else {
        unplaced.insert(id);
      }
    }
    // A node the warm start lacks (an object only merge candidates bring in) starts where its tie
    // to a placed node puts it: as the earlier skeleton solution placed the two relative to each
    // other, or else by the tie, as a solve without the node places a leaf.
    const auto earlier = [&warm](NodeId id) {
      const auto it = warm->last_skeleton.find(id);
      return it == warm->last_skeleton.end() ? std::optional<Eigen::Isometry3d>() : it->second;
    };
    for (const PoseGraphEdge& e : robust.edges) {
      if (e.kind == PoseGraphEdge::Kind::kLoopClosure) continue;
      const bool from = unplaced.count(e.from) != 0, to = unplaced.count(e.to) != 0;
      if (from == to || !initial_poses.count(e.from) || !initial_poses.count(e.to)) continue;
      const NodeId placed = to ? e.from : e.to, node = to ? e.to : e.from;
      const auto placed_then = earlier(placed), node_then = earlier(node);
      initial_poses[node] =
          initial_poses[placed] * (placed_then && node_then ? placed_then->inverse() * *node_then
                                   : to                     ? e.T_from_to
                                                            : e.T_from_to.inverse());
      unplaced.erase(node);
    }
    for (const NodeId id : unplaced) {
      if (const auto then = warm->last_whole.find(id); then != warm->last_whole.end())
        initial_poses[id] = then->second;
    }
  }
  if (warm != nullptr && !warm->admit_if_fitting.empty())
    result.admitted =
        admitFitting(robust, initial_poses, graph.anchor, warm->admit_if_fitting, solver);
  result.solve = optimizePoseGraph(robust, initial_poses, graph.anchor, solver);
  result.poses = result.solve.poses;
  for (size_t i = 0; i < robust.edges.size(); ++i) {
    const PoseGraphEdge& e = robust.edges[i];
    if (e.kind == PoseGraphEdge::Kind::kLoopClosure && i < result.solve.edge_inlier.size())
      result.robust_inlier[{e.from, e.to}] = result.solve.edge_inlier[i];
  }
  if (!options.two_stage) return result;

  // The whole graph with the robust factors GNC kept, from the skeleton's solution: control
  // points start where the keyframe that observed them moved them.
  const auto whole_start = std::chrono::steady_clock::now();
  PoseGraph whole;
  whole.edges.reserve(graph.graph.edges.size());
  for (const PoseGraphEdge& e : graph.graph.edges) {
    if (e.kind == PoseGraphEdge::Kind::kLoopClosure) {
      const auto kept = result.robust_inlier.find({e.from, e.to});
      if (kept == result.robust_inlier.end() || !kept->second) continue;
    }
    whole.edges.push_back(e);
  }
  std::map<NodeId, Eigen::Isometry3d> initial = result.poses;
  for (const auto& [id, pose] : graph.initial) {
    if (initial.count(id)) continue;
    const auto keyframe = graph.observed_by.find(id);
    const auto moved = keyframe == graph.observed_by.end() ? result.poses.end()
                                                           : result.poses.find(keyframe->second);
    initial[id] = moved == result.poses.end()
                      ? pose
                      : moved->second * graph.initial.at(keyframe->second).inverse() * pose;
  }
  result.poses = initial;
  if (options.final_iterations == 0) return result;
  if (warm != nullptr) {
    // From the earlier whole solution, moved as the skeleton (or the keyframe) moved since.
    for (auto& [id, pose] : initial) {
      const auto then = warm->last_whole.find(id);
      if (then == warm->last_whole.end()) continue;
      const auto keyframe = graph.observed_by.find(id);
      const NodeId mover = keyframe == graph.observed_by.end() ? id : keyframe->second;
      const auto now = result.solve.poses.find(mover);
      const auto skeleton_then = warm->last_skeleton.find(mover);
      if (now == result.solve.poses.end() || skeleton_then == warm->last_skeleton.end()) continue;
      pose = now->second * skeleton_then->second.inverse() * then->second;
    }
  }
  RobustPgoOptions plain = options.solver;
  plain.robust = false;
  plain.solver.max_iterations = options.final_iterations;
  plain.solver.linear_solver = PoseGraphOptimizerOptions::LinearSolver::kSparseCholesky;
  const std::optional<std::set<NodeId>> changed = options.local_whole_graph && warm != nullptr
                                                      ? changedNodes(whole, initial, *warm, options)
                                                      : std::nullopt;
  if (!changed || changed->size() > options.local_max_share * initial.size()) {
    const RobustPgoResult solved = optimizePoseGraph(whole, initial, graph.anchor, plain);
    if (solved.usable) result.poses = solved.poses;
    result.whole_graph_free = initial.size();
  } else {
    // The factors of the changed nodes, the others they reach held where they are.
    result.poses = initial;
    PoseGraph local;
    std::map<NodeId, Eigen::Isometry3d> local_initial;
    for (const PoseGraphEdge& e : whole.edges) {
      if (!changed->count(e.from) && !changed->count(e.to)) continue;
      local.edges.push_back(e);
      for (const NodeId id : {e.from, e.to}) {
        local_initial[id] = initial.at(id);
        if (!changed->count(id)) plain.constant.insert(id);
      }
    }
    if (!local.edges.empty()) {
      const RobustPgoResult solved = optimizePoseGraph(local, local_initial, graph.anchor, plain);
      if (solved.usable) {
        for (const NodeId id : *changed) result.poses[id] = solved.poses.at(id);
      }
    }
    result.whole_graph_free = changed->size();
  }
  result.whole_graph_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - whole_start).count();
  return result;
}

}  // namespace hydra_multi
