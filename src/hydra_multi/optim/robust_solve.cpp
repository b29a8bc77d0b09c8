#include "hydra_multi/optim/robust_solve.h"

#include <algorithm>
#include <chrono>

namespace hydra_multi {
namespace robust_pgo {

std::string seconds(double s) { return std::to_string(s) + " s"; }

namespace {

// The factorizations a solve asked for in single precision that were made in double, if any.
std::string fallbacks(const SolveSummary& summary) {
  if (summary.single_precision_fallbacks == 0) return "";
  return "; " + std::to_string(summary.single_precision_fallbacks) +
         " factorizations made in double where single precision failed";
}

}  // namespace

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
  problem.posesInto(poses);
  return summary;
}

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

  bool last_converged = false;  // GNC's last solve stopped before its iteration limit
  std::vector<double> edge_weights(graph.edges.size(), 1.0);
  for (const size_t k : held_out) edge_weights[k] = 0.0;
  const auto solve = [&](const std::vector<double>& weights) {
    for (size_t r = 0; r < robust_edges.size(); ++r) edge_weights[robust_edges[r]] = weights[r];
    problem.setWeights(edge_weights);
    if (options.restart_from_initial) problem.resetToInitial();
    if (options.robust && !chosen) chooseLinearSolver();
    const SolveSummary summary = problem.solve();
    record(summary);
    last_converged = summary.usable && summary.iterations < problem.options().max_iterations;
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
                       " loop closures weighted > 0.5" + fallbacks(summary));
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
    problem.posesInto(result.poses);
    result.edge_weight = edge_weights;
    result.edge_inlier.assign(graph.edges.size(), true);
    for (size_t r = 0; r < robust_edges.size(); ++r)
      result.edge_inlier[robust_edges[r]] = result.gnc.inliers[r];
    for (const size_t k : held_out) result.edge_inlier[k] = false;
  };

  // Polish: the exact optimum over the inliers with the configured (sparse) solver (GNC's last
  // solve where it is that already: keep_converged_gnc_solve); then take back rejected loop
  // closures that fit it, and repeat until none does (or, after the second solve, or the first
  // with readmit_unsolved_first, until fewer than readmit_unsolved_share of the inliers do). With
  // sparse Cholesky throughout, the solves reuse GNC's problem (the same optimum: a factor at
  // weight 0 is none).
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
      const bool kept = round == 0 && options.keep_converged_gnc_solve && !conjugate_gradients &&
                        result.gnc.iterations > 0 && last_converged &&
                        result.gnc.stop_reason == "weights converged";
      if (kept) {
        // GNC's last solution (result.poses), the inliers' optimum already.
      } else if (conjugate_gradients) {
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
        problem.posesInto(result.poses);
      }
      if (!kept) record(summary);

      std::vector<size_t> fitting;  // rejected factors that fit the result: re-admitted
      if (options.readmit_consistent) {
        std::vector<size_t> rejected;
        for (const auto* decided : {&robust_edges, &held_out}) {
          for (const size_t k : *decided) {
            if (!result.edge_inlier[k]) rejected.push_back(k);
          }
        }
        fitting = edgesThatFit(graph, rejected, result.poses, anchor, options);
        for (const size_t k : fitting) {
          result.edge_inlier[k] = true;
          result.edge_weight[k] = 1.0;
        }
      }
      const size_t readmitted = fitting.size();
      if (options.progress && kept) {
        options.progress("GNC's last solve kept as the solve over the " +
                         std::to_string(inlier_edges) + " inlier edges; " +
                         std::to_string(readmitted) + " rejected loop closures fit it again");
      } else if (options.progress) {
        options.progress("solve over the " + std::to_string(inlier_edges) +
                         " inlier edges: " + std::to_string(summary.iterations) +
                         " iterations in " + seconds(summary.time_s) + ", cost " +
                         std::to_string(summary.initial_cost) + " -> " +
                         std::to_string(summary.final_cost) + "; " + std::to_string(readmitted) +
                         " rejected loop closures fit it again" + fallbacks(summary));
      }
      if (readmitted == 0) break;
      if (round == 0) result.held_out_poses = result.poses;  // re-admission leaves them
      if ((round > 0 || options.readmit_unsolved_first) &&
          static_cast<double>(readmitted) <
              options.readmit_unsolved_share * static_cast<double>(inlier_edges)) {
        result.readmitted_unsolved.insert(result.readmitted_unsolved.end(), fitting.begin(),
                                          fitting.end());
        break;
      }
    }
  };

  if (!options.robust) {
    solve(std::vector<double>(robust_edges.size(), 1.0));
    problem.posesInto(result.poses);
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

}  // namespace robust_pgo
}  // namespace hydra_multi
