#include "hydra_multi/optim/robust_pose_graph.h"

#include <chrono>

namespace hydra_multi {

RobustPgoResult optimizePoseGraph(const PoseGraph& graph,
                                  const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                                  const RobustPgoOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RobustPgoResult result;
  PoseGraphProblem problem(graph, initial, anchor, options.solver);

  // Robust factors: the loop closures the problem includes.
  std::vector<size_t> robust_edges;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    if (graph.edges[k].kind == PoseGraphEdge::Kind::kLoopClosure && problem.edgeIncluded(k)) {
      robust_edges.push_back(k);
    }
  }
  std::vector<double> edge_weights(graph.edges.size(), 1.0);
  const auto solve = [&](const std::vector<double>& weights) {
    for (size_t r = 0; r < robust_edges.size(); ++r) edge_weights[robust_edges[r]] = weights[r];
    problem.setWeights(edge_weights);
    if (options.restart_from_initial) problem.resetToInitial();
    const SolveSummary summary = problem.solve();
    result.solver_iterations += summary.iterations;
    ++result.solves;
    result.final_cost = summary.final_cost;
    result.usable = summary.usable;
    result.message = summary.message;
    WeightedSolution solution;
    solution.cost = summary.final_cost;
    const std::vector<double> r2 = problem.squaredResiduals();
    for (const size_t k : robust_edges) solution.squared_residuals.push_back(r2[k]);
    return solution;
  };

  if (options.robust) {
    result.gnc = runGnc(robust_edges.size(), solve, options.gnc);
  } else {
    solve(std::vector<double>(robust_edges.size(), 1.0));
  }
  result.poses = problem.poses();
  result.edge_weight = edge_weights;
  result.edge_inlier.assign(graph.edges.size(), true);
  for (size_t r = 0; r < robust_edges.size() && options.robust; ++r) {
    result.edge_inlier[robust_edges[r]] = result.gnc.inliers[r];
  }
  result.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace hydra_multi
