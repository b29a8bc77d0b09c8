#include "hydra_multi/optim/robust_pose_graph.h"

#include <algorithm>
#include <chrono>
#include <unordered_map>

#include "hydra_multi/optim/pose_graph_chains.h"

namespace hydra_multi {
namespace {

std::string seconds(double s) { return std::to_string(s) + " s"; }

// One solve, from `poses`, of a problem made of the edges of `graph` that `inlier` says (the
// options' constant poses held); `poses` becomes its solution.
SolveSummary solveOverInliers(const PoseGraph& graph, const std::vector<bool>& inlier,
                              std::map<NodeId, Eigen::Isometry3d>& poses, NodeId anchor,
                              const RobustPgoOptions& options) {
  PoseGraph inliers;
  inliers.edges.reserve(graph.edges.size());
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    if (inlier[k]) inliers.edges.push_back(graph.edges[k]);
  }
  PoseGraphProblem problem(inliers, poses, anchor, options.solver);
  if (!options.constant.empty()) problem.holdConstant(options.constant);
  const SolveSummary summary = problem.solve();
  poses = problem.poses();
  return summary;
}

// Per edge of the graph a solve sees: the factors GNC holds out and those known to be inliers
// (RobustPgoOptions::held_out and known_inlier; shorter: the rest are neither).
struct EdgeFlags {
  std::vector<bool> held_out, known_inlier;
  bool heldOut(size_t k) const { return k < held_out.size() && held_out[k]; }
  bool known(size_t k) const { return k < known_inlier.size() && known_inlier[k]; }
};

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

// The solve of optimizePoseGraph without leaves (their poses absent from `initial`, which leaves
// their edges out) and without chains, when reduced; `flags` per edge of `graph`.
RobustPgoResult optimizeReduced(const PoseGraph& graph,
                                const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                                const RobustPgoOptions& options, const EdgeFlags& flags) {
  const auto start = std::chrono::steady_clock::now();
  RobustPgoResult result;
  PoseGraphProblem problem(graph, initial, anchor, options.solver);
  if (!options.constant.empty()) problem.holdConstant(options.constant);

  // Robust factors: the loop closures the problem includes, undecided, held out or known inliers.
  std::vector<size_t> robust_edges, held_out, known;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    if (graph.edges[k].kind != PoseGraphEdge::Kind::kLoopClosure || !problem.edgeIncluded(k))
      continue;
    if (flags.heldOut(k)) {
      held_out.push_back(k);
    } else if (options.robust && flags.known(k)) {
      known.push_back(k);
    } else {
      robust_edges.push_back(k);
    }
  }

  // The held-out factors stay at weight 0 until re-admitted: out of the problem until then, they
  // add no fill-in to GNC's factorizations (the polish brings back those it re-admits).
  const auto leaveOutRejected = [&] {
    std::vector<bool> out(graph.edges.size(), false);
    for (const size_t k : held_out) {
      out[k] = result.edge_inlier.empty() || !result.edge_inlier[k];
    }
    problem.leaveOut(out);
  };
  leaveOutRejected();

  // Before GNC's first solve, the factor's fill decides the linear solver (see options).
  bool conjugate_gradients = false, chosen = false;
  const auto chooseLinearSolver = [&]() {
    chosen = true;
    const double mflops = problem.choleskyFlopsPerPose() / 1e6;
    conjugate_gradients = mflops > options.cholesky_mflops_per_pose_limit;
    PoseGraphOptimizerOptions inner = options.solver;
    if (options.gnc_inner_iterations > 0) inner.max_iterations = options.gnc_inner_iterations;
    if (conjugate_gradients) {
      inner.linear_solver = PoseGraphOptimizerOptions::LinearSolver::kConjugateGradients;
    }
    problem.setOptions(inner);
    if (options.progress) {
      options.progress(
          "a sparse Cholesky factorization takes " + std::to_string(mflops) +
          " MFLOP per pose: " + (conjugate_gradients ? "conjugate gradients" : "sparse Cholesky") +
          " for the GNC solves");
    }
  };

  // Every solve counts into the result's totals; the last one's report stays.
  const auto record = [&result](const SolveSummary& summary) {
    ++result.solves;
    result.solver_time += summary;
    result.final_cost = summary.final_cost;
    result.usable = summary.usable;
    result.message = summary.message;
  };

  std::vector<double> edge_weights(graph.edges.size(), 1.0);
  for (const size_t k : held_out) edge_weights[k] = 0.0;
  const auto solve = [&](const std::vector<double>& weights) {
    for (size_t r = 0; r < robust_edges.size(); ++r) edge_weights[robust_edges[r]] = weights[r];
    problem.setWeights(edge_weights);
    if (options.restart_from_initial) problem.resetToInitial();
    if (options.robust && !chosen) chooseLinearSolver();
    const SolveSummary summary = problem.solve();
    record(summary);
    WeightedSolution solution;
    solution.cost = summary.final_cost;
    const std::vector<double> r2 = problem.squaredResiduals();
    for (const size_t k : robust_edges) solution.squared_residuals.push_back(r2[k]);
    if (options.progress) {
      size_t kept = 0;
      for (const double w : weights) kept += w > 0.5 ? 1 : 0;
      options.progress("solve " + std::to_string(result.solves) + ": " +
                       std::to_string(summary.iterations) + " iterations in " +
                       seconds(summary.time_s) + ", cost " + std::to_string(summary.final_cost) +
                       ", " + std::to_string(kept) + " of " + std::to_string(weights.size()) +
                       " loop closures weighted > 0.5");
    }
    return solution;
  };

  // GNC over the undecided robust factors (none: nothing to run), from the problem's poses.
  const auto gnc = [&] {
    std::vector<double> initial_r2;
    if (options.gnc_from_initial_estimate) {
      const std::vector<double> r2 = problem.squaredResiduals();
      for (const size_t k : robust_edges) initial_r2.push_back(r2[k]);
    }
    GncOptions schedule = options.gnc;
    if (options.incremental_mu_step > 1.0 && known.size() >= robust_edges.size())
      schedule.mu_step = options.incremental_mu_step;
    result.gnc = runGnc(robust_edges.size(), solve, schedule,
                        options.gnc_from_initial_estimate ? &initial_r2 : nullptr);
    result.poses = problem.poses();
    result.edge_weight = edge_weights;
    result.edge_inlier.assign(graph.edges.size(), true);
    for (size_t r = 0; r < robust_edges.size(); ++r)
      result.edge_inlier[robust_edges[r]] = result.gnc.inliers[r];
    for (const size_t k : held_out) result.edge_inlier[k] = false;
  };

  // Polish: the exact optimum over the inliers with the configured (sparse) solver; then take
  // back rejected loop closures that fit it, and repeat until none does (or, after the second
  // solve, until fewer than readmit_unsolved_share of the inliers do). With sparse Cholesky
  // throughout, the solves reuse GNC's problem (the same optimum: a factor at weight 0 is none).
  const double c2 = options.gnc.thresholdSq();
  const auto inlierCost = [&](const std::map<NodeId, Eigen::Isometry3d>& poses) {
    const std::vector<double> r2 = problem.setPoses(poses).squaredResiduals();
    double cost = 0.0;
    for (size_t k = 0; k < r2.size(); ++k) cost += result.edge_inlier[k] ? r2[k] : 0.0;
    return cost;
  };
  const auto polish = [&] {
    for (int round = 0; round < 10; ++round) {
      leaveOutRejected();  // those re-admitted last round back in
      size_t inlier_edges = 0;
      for (size_t k = 0; k < graph.edges.size(); ++k)
        inlier_edges += result.edge_inlier[k] && problem.edgeIncluded(k) ? 1 : 0;
      if (round > 0 && !options.earlier_held_out.empty()) {
        // After a re-admission: from the held-out solution moved as the earlier solve's
        // re-admission moved its own, H_now H_then^-1 F_then, when that fits the inliers better
        // than the solution the re-admission adds to.
        std::map<NodeId, Eigen::Isometry3d> moved = result.poses;
        for (auto& [id, pose] : moved) {
          const auto now = result.held_out_poses.find(id);
          const auto then = options.earlier_held_out.find(id);
          const auto readmitted = options.earlier_readmitted.find(id);
          if (now != result.held_out_poses.end() && then != options.earlier_held_out.end() &&
              readmitted != options.earlier_readmitted.end())
            pose = now->second * then->second.inverse() * readmitted->second;
        }
        if (inlierCost(moved) < inlierCost(result.poses)) result.poses = std::move(moved);
      }
      SolveSummary summary;
      if (conjugate_gradients) {
        // A problem over the inliers alone: the outliers' fill-in is what made GNC use CG.
        summary = solveOverInliers(graph, result.edge_inlier, result.poses, anchor, options);
      } else {
        // GNC's problem, its analysis and factor kept, with the rejected at weight 0.
        const PoseGraphOptimizerOptions inner = problem.options();
        std::vector<double> weights(graph.edges.size());
        for (size_t k = 0; k < weights.size(); ++k) weights[k] = result.edge_inlier[k] ? 1.0 : 0.0;
        problem.setWeights(weights);
        problem.setPoses(result.poses);
        problem.setOptions(options.solver);
        summary = problem.solve();
        problem.setOptions(inner);
        result.poses = problem.poses();
      }
      record(summary);

      size_t readmitted = 0;
      if (options.readmit_consistent) {
        std::vector<size_t> rejected;
        for (const auto* decided : {&robust_edges, &held_out}) {
          for (const size_t k : *decided) {
            if (!result.edge_inlier[k]) rejected.push_back(k);
          }
        }
        for (const size_t k : edgesThatFit(graph, rejected, result.poses, anchor, options)) {
          result.edge_inlier[k] = true;
          result.edge_weight[k] = 1.0;
          ++readmitted;
        }
      }
      if (options.progress) {
        options.progress("solve over the " + std::to_string(inlier_edges) +
                         " inlier edges: " + std::to_string(summary.iterations) +
                         " iterations in " + seconds(summary.time_s) + ", cost " +
                         std::to_string(summary.initial_cost) + " -> " +
                         std::to_string(summary.final_cost) + "; " + std::to_string(readmitted) +
                         " rejected loop closures fit it again");
      }
      if (readmitted == 0) break;
      if (round == 0) result.held_out_poses = result.poses;  // re-admission leaves them
      if (round > 0 && static_cast<double>(readmitted) <
                           options.readmit_unsolved_share * static_cast<double>(inlier_edges))
        break;
    }
  };

  if (!options.robust) {
    solve(std::vector<double>(robust_edges.size(), 1.0));
    result.poses = problem.poses();
    result.edge_weight = edge_weights;
    result.edge_inlier.assign(graph.edges.size(), true);
  } else {
    gnc();
    // With nothing undecided GNC did not solve: the polish is the solve.
    if (conjugate_gradients || options.readmit_consistent || result.solves == 0) polish();
    // Known inliers the result contradicts are decided again by GNC from it, with the factors
    // decided so far fixed: inliers at weight 1, the rejected held out.
    if (!known.empty()) {
      const std::vector<double> r2 = problem.setPoses(result.poses).squaredResiduals();
      std::vector<size_t> contradicted;
      for (const size_t k : known) {
        if (r2[k] > c2) contradicted.push_back(k);
      }
      if (!contradicted.empty()) {
        result.known_contradicted = contradicted.size();
        std::vector<size_t> decided = robust_edges;
        decided.insert(decided.end(), held_out.begin(), held_out.end());
        held_out.clear();
        for (const size_t k : decided) {
          if (result.edge_inlier[k]) {
            known.push_back(k);
          } else {
            held_out.push_back(k);
            edge_weights[k] = 0.0;
          }
        }
        for (const size_t k : contradicted) {
          known.erase(std::find(known.begin(), known.end(), k));
        }
        for (const size_t k : known) edge_weights[k] = 1.0;
        robust_edges = contradicted;
        gnc();
        polish();
      }
    }
  }
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
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
  std::unordered_map<NodeId, int> degree;
  const auto included = [&](size_t k) {
    const PoseGraphEdge& e = graph.edges[k];
    return e.from != e.to && initial.count(e.from) && initial.count(e.to) &&
           (options.robust || !flags.heldOut(k));
  };
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    if (!included(k)) continue;
    ++degree[graph.edges[k].from];
    ++degree[graph.edges[k].to];
  }
  const auto isLeaf = [&](NodeId id) {
    return id != anchor && degree[id] == 1 && options.constant.count(id) == 0;
  };
  std::vector<size_t> leaf_edges;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (included(k) && e.kind != PoseGraphEdge::Kind::kLoopClosure &&
        isLeaf(e.from) != isLeaf(e.to))
      leaf_edges.push_back(k);
  }
  // Without the leaves' poses the problem leaves their edges out: no copy of the graph.
  std::map<NodeId, Eigen::Isometry3d> reduced_initial;
  if (!leaf_edges.empty()) reduced_initial = initial;
  for (const size_t k : leaf_edges) {
    const PoseGraphEdge& e = graph.edges[k];
    reduced_initial.erase(isLeaf(e.to) ? e.to : e.from);
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
    if (isLeaf(e.to))
      result.poses[e.to] = at(e.from) * e.T_from_to;
    else
      result.poses[e.from] = at(e.to) * e.T_from_to.inverse();
  }
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace hydra_multi
