#include "hydra_multi/optim/robust_pose_graph.h"

#include <algorithm>
#include <chrono>
#include <unordered_map>
#include <unordered_set>

#include "hydra_multi/optim/pose_graph_chains.h"
#include "hydra_multi/optim/robust_solve.h"

namespace hydra_multi {
namespace {

using robust_pgo::EdgeFlags;
using robust_pgo::optimizeReduced;
using robust_pgo::seconds;
using robust_pgo::solveOverInliers;

// A problem made of some of a graph's edges (`kept`, by index) and `extra` ones after them: its
// graph, and each kept edge's flags.
struct SubProblem {
  PoseGraph graph;
  EdgeFlags flags;
};
SubProblem subProblem(const PoseGraph& graph, const EdgeFlags& flags,
                      const std::vector<size_t>& kept,
                      const std::vector<PoseGraphEdge>& extra = {}) {
  SubProblem sub;
  sub.graph.edges.reserve(kept.size() + extra.size());
  for (const size_t k : kept) {
    sub.graph.edges.push_back(graph.edges[k]);
    sub.flags.held_out.push_back(flags.heldOut(k));
    sub.flags.known_inlier.push_back(flags.known(k));
  }
  sub.graph.edges.insert(sub.graph.edges.end(), extra.begin(), extra.end());
  return sub;
}

// The verdicts and weights of a sub-problem's result (subProblem) per edge of the graph of `edges`
// edges: the kept edges' from the result, the others inliers at weight 1.
void verdictsOfGraph(RobustPgoResult& result, const std::vector<size_t>& kept, size_t edges) {
  std::vector<bool> edge_inlier(edges, true);
  std::vector<double> edge_weight(edges, 1.0);
  for (size_t r = 0; r < kept.size(); ++r) {
    if (r < result.edge_inlier.size()) edge_inlier[kept[r]] = result.edge_inlier[r];
    if (r < result.edge_weight.size()) edge_weight[kept[r]] = result.edge_weight[r];
  }
  result.edge_inlier = std::move(edge_inlier);
  result.edge_weight = std::move(edge_weight);
}

// The solve of optimizePoseGraph without leaves (as optimizeReduced): its chains
// (pose_graph_chains.h) reduced to one edge each, their interiors placed after, and then one solve
// of the whole graph over the inliers from there.
RobustPgoResult optimizeWithoutLeaves(const PoseGraph& graph,
                                      const std::map<NodeId, Eigen::Isometry3d>& initial,
                                      NodeId anchor, const RobustPgoOptions& options,
                                      const EdgeFlags& flags) {
  if (!options.reduce_chains || !options.robust)
    return optimizeReduced(graph, initial, anchor, options, flags);
  const auto start = std::chrono::steady_clock::now();
  const ChainReduction reduction = findChains(graph, initial, anchor, options.constant);
  size_t interior = 0;
  for (const PoseGraphChain& chain : reduction.chains) interior += chain.interior.size();
  if (interior == 0 || interior < options.chain_min_share * initial.size())
    return optimizeReduced(graph, initial, anchor, options, flags);

  const SubProblem reduced = subProblem(graph, flags, reduction.kept_edges, reduction.composed);
  std::map<NodeId, Eigen::Isometry3d> reduced_initial = initial;
  for (const PoseGraphChain& chain : reduction.chains) {
    for (const NodeId id : chain.interior) reduced_initial.erase(id);
  }
  RobustPgoResult result =
      optimizeReduced(reduced.graph, reduced_initial, anchor, options, reduced.flags);
  placeChainInteriors(graph, reduction, result.poses);
  if (!result.held_out_poses.empty()) placeChainInteriors(graph, reduction, result.held_out_poses);
  verdictsOfGraph(result, reduction.kept_edges, graph.edges.size());

  // The interiors sit at the first-order optimum; the solve over the inliers makes it exact.
  const SolveSummary summary =
      solveOverInliers(graph, result.edge_inlier, result.poses, anchor, options);
  result.readmitted_unsolved.clear();  // solved in by it (and numbered in the reduced graph)
  ++result.solves;
  result.solver_time += summary;
  result.final_cost = summary.final_cost;
  result.usable = result.usable && summary.usable;
  result.message = summary.message;
  if (options.progress) {
    options.progress("solve of the " + std::to_string(reduction.chains.size()) +
                     " chains' poses with the rest: " + std::to_string(summary.iterations) +
                     " iterations in " + seconds(summary.time_s) + ", cost " +
                     std::to_string(summary.initial_cost) + " -> " +
                     std::to_string(summary.final_cost));
  }
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

std::vector<size_t> edgesThatFit(const PoseGraph& graph, const std::vector<size_t>& candidates,
                                 const std::map<NodeId, Eigen::Isometry3d>& poses, NodeId anchor,
                                 const RobustPgoOptions& options) {
  PoseGraph placed;
  std::vector<size_t> index;
  for (const size_t k : candidates) {
    const PoseGraphEdge& e = graph.edges[k];
    if (!poses.count(e.from) || !poses.count(e.to)) continue;
    placed.edges.push_back(e);
    index.push_back(k);
  }
  const std::vector<double> r2 =
      PoseGraphProblem(placed, poses, anchor, options.solver).squaredResiduals();
  const double c2 = options.gnc.thresholdSq();
  std::vector<size_t> fit;
  for (size_t i = 0; i < index.size(); ++i) {
    if (r2[i] <= c2) fit.push_back(index[i]);
  }
  return fit;
}

RobustPgoResult optimizePoseGraph(const PoseGraph& graph,
                                  const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                                  const RobustPgoOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  // Leaves: poses with one edge, a known inlier (not a loop closure), other than the anchor and
  // the poses held constant. The held-out factors of a solve that is not robust count for nothing.
  const EdgeFlags flags{options.held_out, options.known_inlier};
  // Each pose's count of included edges: between two poses of `initial`, not a self-loop, and,
  // unless the solve is robust, not held out.
  std::unordered_map<NodeId, int> degree;
  degree.reserve(initial.size());
  for (const auto& [id, pose] : initial) degree.emplace(id, 0);
  std::vector<char> included(graph.edges.size(), 0);
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (e.from == e.to || (!options.robust && flags.heldOut(k))) continue;
    const auto from = degree.find(e.from), to = degree.find(e.to);
    if (from == degree.end() || to == degree.end()) continue;
    included[k] = 1;
    ++from->second;
    ++to->second;
  }
  const auto isLeaf = [&](NodeId id) {
    return id != anchor && degree.at(id) == 1 && options.constant.count(id) == 0;
  };
  std::vector<size_t> leaf_edges;
  std::unordered_set<NodeId> leaves;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (!included[k] || e.kind == PoseGraphEdge::Kind::kLoopClosure) continue;
    const bool from = isLeaf(e.from), to = isLeaf(e.to);
    if (from == to) continue;
    leaf_edges.push_back(k);
    leaves.insert(to ? e.to : e.from);
  }
  // Without the leaves' poses the problem leaves their edges out: no copy of the graph.
  std::map<NodeId, Eigen::Isometry3d> reduced_initial;
  if (!leaf_edges.empty()) {
    for (const auto& [id, pose] : initial) {
      if (!leaves.count(id)) reduced_initial.emplace_hint(reduced_initial.end(), id, pose);
    }
  }
  RobustPgoResult result = optimizeWithoutLeaves(
      graph, leaf_edges.empty() ? initial : reduced_initial, anchor, options, flags);
  if (!options.robust) {  // held out, and so no part of the solve: rejected
    for (size_t k = 0; k < graph.edges.size(); ++k) {
      if (!flags.heldOut(k)) continue;
      result.edge_inlier[k] = false;
      result.edge_weight[k] = 0.0;
    }
  }
  // Each leaf where its edge puts it: that edge's residual is zero, the optimum's exactly.
  for (const size_t k : leaf_edges) {
    const PoseGraphEdge& e = graph.edges[k];
    const auto at = [&](NodeId id) {
      const auto it = result.poses.find(id);
      return it != result.poses.end() ? it->second : initial.at(id);
    };
    if (leaves.count(e.to))
      result.poses[e.to] = at(e.from) * e.T_from_to;
    else
      result.poses[e.from] = at(e.to) * e.T_from_to.inverse();
  }
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace hydra_multi
