// The deformation graph's solve (deformation_graph.h: optimizeDeformationGraph): GNC over the
// skeleton, from a warm start where there is one, then the whole graph where the skeleton moved it.
#include "hydra_multi/backend/deformation_graph.h"

#include <algorithm>
#include <chrono>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <set>

#include "hydra_multi/core/ascending_lookup.h"
#include "hydra_multi/core/background_task.h"
#include "hydra_multi/optim/sparse_levenberg_marquardt.h"

namespace hydra_multi {
namespace {

// The nodes a warm-started whole-graph solve moves (DeformationGraphOptions::local_whole_graph):
// those of the factors whose two poses are placed relative to each other otherwise than in the
// earlier solution (or that it lacks), the ends of `unsolved` (factors no solve has solved in),
// and those within local_hops edges of them; none without an earlier solution.
std::optional<std::set<NodeId>> changedNodes(const PoseGraph& whole,
                                             const std::vector<bool>& left_out,
                                             const std::map<NodeId, Eigen::Isometry3d>& start,
                                             const DeformationWarmStart& warm,
                                             const std::vector<PoseGraphEdge>& unsolved,
                                             const DeformationGraphOptions& options) {
  if (warm.last_whole.empty()) return std::nullopt;
  // Per node of `start`, by its place in id order: its pose there and in the earlier solution
  // (none: null), its neighbours (those of node i: neighbours[first[i]..first[i + 1])).
  const size_t n = start.size();
  std::vector<NodeId> ids;
  std::vector<const Eigen::Isometry3d*> now, then;
  ids.reserve(n);
  now.reserve(n);
  then.reserve(n);
  AscendingLookup earlier(warm.last_whole);
  for (const auto& [id, pose] : start) {
    ids.push_back(id);
    now.push_back(&pose);
    then.push_back(earlier.find(id));
  }
  constexpr size_t kAbsent = std::numeric_limits<size_t>::max();
  const auto indexOf = [&ids](NodeId id) {
    const auto it = std::lower_bound(ids.begin(), ids.end(), id);
    return it != ids.end() && *it == id ? size_t(it - ids.begin()) : kAbsent;
  };
  std::vector<char> changed(n, 0);
  std::vector<std::pair<size_t, size_t>> joined;  // the solved factors' ends, both in `start`
  joined.reserve(whole.edges.size());
  for (size_t k = 0; k < whole.edges.size(); ++k) {
    const PoseGraphEdge& e = whole.edges[k];
    if (left_out[k]) continue;
    const size_t a = indexOf(e.from), b = indexOf(e.to);
    if (a == kAbsent || b == kAbsent) continue;
    joined.emplace_back(a, b);
    bool moved = then[a] == nullptr || then[b] == nullptr;
    if (!moved) {
      const Eigen::Isometry3d delta =
          (then[a]->inverse() * *then[b]).inverse() * (now[a]->inverse() * *now[b]);
      moved = delta.translation().norm() > options.local_move_m ||
              Eigen::AngleAxisd(delta.linear()).angle() > options.local_move_rad;
    }
    if (moved) changed[a] = changed[b] = 1;
  }
  for (const PoseGraphEdge& e : unsolved) {
    const size_t a = indexOf(e.from), b = indexOf(e.to);
    if (a != kAbsent && b != kAbsent) changed[a] = changed[b] = 1;
  }
  std::vector<size_t> first(n + 1, 0), neighbours(2 * joined.size());
  for (const auto& [a, b] : joined) {
    ++first[a + 1];
    ++first[b + 1];
  }
  for (size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  std::vector<size_t> next_slot(first.begin(), first.end() - 1);
  for (const auto& [a, b] : joined) {
    neighbours[next_slot[a]++] = b;
    neighbours[next_slot[b]++] = a;
  }
  std::vector<size_t> frontier;
  for (size_t i = 0; i < n; ++i) {
    if (changed[i]) frontier.push_back(i);
  }
  for (int hop = 0; hop < options.local_hops && !frontier.empty(); ++hop) {
    std::vector<size_t> reached;
    for (const size_t i : frontier) {
      for (size_t j = first[i]; j < first[i + 1]; ++j) {
        const size_t other = neighbours[j];
        if (changed[other]) continue;
        changed[other] = 1;
        reached.push_back(other);
      }
    }
    frontier = std::move(reached);
  }
  std::set<NodeId> result;
  for (size_t i = 0; i < n; ++i) {
    if (changed[i]) result.emplace_hint(result.end(), ids[i]);
  }
  return result;
}

// The pose of `id` in `poses`, or null.
const Eigen::Isometry3d* poseIn(const std::map<NodeId, Eigen::Isometry3d>& poses, NodeId id) {
  const auto it = poses.find(id);
  return it == poses.end() ? nullptr : &it->second;
}

// The held-out factors of `candidates` (from, to) that fit `poses` (edgesThatFit) become known
// inliers of `solver`; returns how many.
size_t admitFitting(const PoseGraph& graph, const std::map<NodeId, Eigen::Isometry3d>& poses,
                    NodeId anchor, const std::set<std::pair<NodeId, NodeId>>& candidates,
                    RobustPgoOptions& solver) {
  std::vector<size_t> held;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (solver.held_out[k] && candidates.count({e.from, e.to})) held.push_back(k);
  }
  const std::vector<size_t> fit = edgesThatFit(graph, held, poses, anchor, solver);
  for (const size_t k : fit) {
    solver.held_out[k] = false;
    solver.known_inlier[k] = true;
  }
  return fit.size();
}

// Per edge of the whole graph: the robust factors (from, to) `kept` does not say true of, which
// the whole-graph solve leaves out (held out of a solve that is not robust: no part of it).
std::vector<bool> leftOut(const DeformationGraph& graph,
                          const std::map<std::pair<NodeId, NodeId>, bool>& kept) {
  std::vector<bool> out(graph.graph.edges.size(), false);
  for (size_t k = 0; k < out.size(); ++k) {
    const PoseGraphEdge& e = graph.graph.edges[k];
    if (e.kind != PoseGraphEdge::Kind::kLoopClosure) continue;
    const auto it = kept.find({e.from, e.to});
    out[k] = it == kept.end() || !it->second;
  }
  return out;
}

// The whole-graph solve's options: least squares over what GNC kept, sparse Cholesky.
RobustPgoOptions wholeGraphSolver(const DeformationGraphOptions& options) {
  RobustPgoOptions plain = options.solver;
  plain.robust = false;
  plain.solver.max_iterations = options.final_iterations;
  plain.solver.linear_solver = PoseGraphOptimizerOptions::LinearSolver::kSparseCholesky;
  return plain;
}

// The sparse analysis of the whole-graph solve GNC's result is expected to lead to (the robust
// factors of `robust` it starts with all kept, and the merges it holds out, which it takes back
// where they fit; the loop closures it holds out rejected), made into `ahead`
// (PoseGraphOptimizerOptions::analyses). Its nodes are the whole graph's, as the solve's.
void analyzeWholeGraphAhead(const DeformationGraph& graph, const PoseGraph& robust,
                            const std::vector<bool>& held_out,
                            const DeformationGraphOptions& options,
                            const std::shared_ptr<SparseAnalyses>& ahead) {
  if (ahead->dropped()) return;
  std::map<std::pair<NodeId, NodeId>, bool> expected;
  for (size_t k = 0; k < robust.edges.size(); ++k) {
    const PoseGraphEdge& e = robust.edges[k];
    if (e.kind == PoseGraphEdge::Kind::kLoopClosure)
      expected[{e.from, e.to}] = !held_out[k] || graph.merge_factors.count({e.from, e.to}) != 0;
  }
  RobustPgoOptions analyze = wholeGraphSolver(options);
  analyze.solver.max_iterations = 0;
  analyze.solver.linearization_threads = 1;
  analyze.solver.analyses = ahead;
  analyze.solver.keep_analysis = true;
  analyze.held_out = leftOut(graph, expected);
  optimizePoseGraph(graph.graph, graph.initial, graph.anchor, analyze);
}

}  // namespace

DeformationResult optimizeDeformationGraph(
    const DeformationGraph& graph, const DeformationGraphOptions& options,
    const std::set<std::pair<NodeId, NodeId>>& held_out, const DeformationWarmStart* warm,
    const std::function<void(const RobustVerdicts&)>& decided,
    const std::function<void(const RobustVerdicts&)>& expected) {
  DeformationResult result;
  if (graph.initial.empty()) return result;
  const PoseGraph& robust = options.two_stage ? graph.skeleton : graph.graph;
  const std::map<NodeId, Eigen::Isometry3d>& robust_poses =
      options.two_stage ? graph.skeleton.poses : graph.initial;
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
  std::map<NodeId, Eigen::Isometry3d> initial_poses = robust_poses;
  if (warm != nullptr) {
    std::set<NodeId> unplaced;
    AscendingLookup warm_poses(warm->poses);
    for (auto& [id, pose] : initial_poses) {
      if (const Eigen::Isometry3d* start = warm_poses.find(id)) {
        pose = *start;
      } else {
        unplaced.emplace_hint(unplaced.end(), id);
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
  if (expected) {
    RobustVerdicts kept;
    for (size_t k = 0; k < robust.edges.size(); ++k) {
      const PoseGraphEdge& e = robust.edges[k];
      if (e.kind == PoseGraphEdge::Kind::kLoopClosure) kept[{e.from, e.to}] = !solver.held_out[k];
    }
    expected(kept);
  }
  // The whole-graph solve's analysis on a second thread while GNC runs (a failure there leaves
  // the solve to analyze its own); dropped where the solve turns out local.
  std::shared_ptr<SparseAnalyses> ahead;
  std::future<void> analyzing;
  if (options.two_stage && options.final_iterations > 0 && options.whole_graph_analysis_ahead) {
    ahead = std::make_shared<SparseAnalyses>();
    analyzing = startInBackground([&graph, &robust, &solver, &options, ahead] {
      try {
        analyzeWholeGraphAhead(graph, robust, solver.held_out, options, ahead);
      } catch (const std::exception&) {
      }
    });
  }
  result.solve = optimizePoseGraph(robust, initial_poses, graph.anchor, solver);
  result.solver_time = result.solve.solver_time;
  for (size_t i = 0; i < robust.edges.size(); ++i) {
    const PoseGraphEdge& e = robust.edges[i];
    if (e.kind == PoseGraphEdge::Kind::kLoopClosure && i < result.solve.edge_inlier.size())
      result.robust_inlier[{e.from, e.to}] = result.solve.edge_inlier[i];
  }
  if (decided) decided(result.robust_inlier);
  if (!options.two_stage) {
    result.poses = result.solve.poses;
    return result;
  }

  // The whole graph with the robust factors GNC kept, from the skeleton's solution: control
  // points start where the keyframe that observed them moved them.
  const auto whole_start = std::chrono::steady_clock::now();
  std::map<NodeId, Eigen::Isometry3d> initial = result.solve.poses;
  AscendingLookup observed_by(graph.observed_by);
  auto next = initial.begin();  // walked with graph.initial, both in id order
  for (const auto& [id, pose] : graph.initial) {
    while (next != initial.end() && next->first < id) ++next;
    if (next != initial.end() && next->first == id) continue;
    const NodeId* keyframe = observed_by.find(id);
    const auto moved =
        keyframe == nullptr ? result.solve.poses.end() : result.solve.poses.find(*keyframe);
    initial.emplace_hint(next, id,
                         moved == result.solve.poses.end()
                             ? pose
                             : moved->second * graph.initial.at(*keyframe).inverse() * pose);
  }
  if (options.final_iterations == 0) {
    result.poses = std::move(initial);
    return result;
  }
  const PoseGraph& whole = graph.graph;
  const std::vector<bool> left_out = leftOut(graph, result.robust_inlier);
  if (warm != nullptr) {
    // From the earlier whole solution, moved as the skeleton (or the keyframe) moved since: by
    // S_now S_then^-1, looked up in id order for a node's own, kept for the last keyframe asked
    // (a keyframe's control points come in a run).
    AscendingLookup last_whole(warm->last_whole);
    AscendingLookup observed(graph.observed_by);
    AscendingLookup own_now(result.solve.poses);
    AscendingLookup own_then(warm->last_skeleton);
    const auto motion = [](const Eigen::Isometry3d* now, const Eigen::Isometry3d* then) {
      return now != nullptr && then != nullptr
                 ? std::optional<Eigen::Isometry3d>(*now * then->inverse())
                 : std::nullopt;
    };
    std::optional<NodeId> keyframe_asked;
    std::optional<Eigen::Isometry3d> keyframe_motion;
    for (auto& [id, pose] : initial) {
      const Eigen::Isometry3d* then = last_whole.find(id);
      if (then == nullptr) continue;
      const NodeId* keyframe = observed.find(id);
      std::optional<Eigen::Isometry3d> moved;
      if (keyframe == nullptr) {
        moved = motion(own_now.find(id), own_then.find(id));
      } else {
        if (keyframe_asked != *keyframe) {
          keyframe_asked = *keyframe;
          keyframe_motion =
              motion(poseIn(result.solve.poses, *keyframe), poseIn(warm->last_skeleton, *keyframe));
        }
        moved = keyframe_motion;
      }
      if (moved) pose = *moved * *then;
    }
  }
  RobustPgoOptions plain = wholeGraphSolver(options);
  // Factors the skeleton took back without solving them in: the whole graph's solve does.
  std::vector<PoseGraphEdge> unsolved;
  for (const size_t k : result.solve.readmitted_unsolved) unsolved.push_back(robust.edges[k]);
  const std::optional<std::set<NodeId>> changed =
      options.local_whole_graph && warm != nullptr && !warm->whole_owed
          ? changedNodes(whole, left_out, initial, *warm, unsolved, options)
          : std::nullopt;
  const double nodes = static_cast<double>(initial.size());
  if (!changed ||
      changed->size() > std::max(options.local_max_share, options.local_deferred_share) * nodes) {
    if (analyzing.valid()) analyzing.wait();
    const bool prepared = ahead != nullptr && ahead->holds();
    plain.solver.analyses = ahead;
    plain.held_out = left_out;
    RobustPgoResult solved = optimizePoseGraph(whole, initial, graph.anchor, plain);
    result.solver_time += solved.solver_time;
    result.whole_graph_analyzed_ahead = prepared && !ahead->holds();
    result.whole_graph_free = initial.size();
    result.poses = solved.usable ? std::move(solved.poses) : std::move(initial);
  } else {
    // Unused: it stops where it is, and its factor's block goes back for the local solve's.
    if (ahead != nullptr) ahead->drop();
    // The factors of the changed nodes, the others they reach held where they are.
    PoseGraph local;
    std::map<NodeId, Eigen::Isometry3d> local_initial;
    for (size_t k = 0; k < whole.edges.size(); ++k) {
      const PoseGraphEdge& e = whole.edges[k];
      if (left_out[k] || (!changed->count(e.from) && !changed->count(e.to))) continue;
      local.edges.push_back(e);
      for (const NodeId id : {e.from, e.to}) {
        local_initial[id] = initial.at(id);
        if (!changed->count(id)) plain.constant.insert(id);
      }
    }
    result.poses = std::move(initial);
    if (!local.edges.empty()) {
      const RobustPgoResult solved = optimizePoseGraph(local, local_initial, graph.anchor, plain);
      result.solver_time += solved.solver_time;
      if (solved.usable) {
        for (const NodeId id : *changed) result.poses[id] = solved.poses.at(id);
      }
    }
    result.whole_graph_free = changed->size();
    result.whole_graph_deferred = changed->size() > options.local_max_share * nodes;
  }
  result.whole_graph_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - whole_start).count();
  return result;
}

}  // namespace hydra_multi
