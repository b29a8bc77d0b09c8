#pragma once
// Pose-graph optimization with or without GNC-TLS over the loop closures (eq. (3) of the paper,
// solved robustly as in Hydra-Multi): odometry edges are known inliers; every loop-closure edge is
// a robust factor whose weight GNC drives to 0 (outlier) or 1 (inlier).

#include <map>

#include "hydra_multi/optim/gnc.h"
#include "hydra_multi/optim/pose_graph_optimizer.h"

namespace hydra_multi {

struct RobustPgoOptions {
  PoseGraphOptimizerOptions solver;
  bool robust = true;  ///< GNC over loop closures; false: one least-squares solve
  GncOptions gnc;
  /// Start every GNC solve from the initial values (GTSAM's choice) instead of the previous
  /// solution (warm start, the default).
  bool restart_from_initial = false;
};

struct RobustPgoResult {
  std::map<NodeId, Eigen::Isometry3d> poses;
  std::vector<bool> edge_inlier;    ///< per graph edge: odometry true, loop closures by GNC
  std::vector<double> edge_weight;  ///< final GNC weight per edge (1 for odometry)
  GncResult gnc;                    ///< empty when not robust
  int solver_iterations = 0;        ///< Levenberg-Marquardt iterations over all solves
  int solves = 0;
  double final_cost = 0.0;  ///< Ceres cost of the last solve (weighted)
  double time_s = 0.0;
  bool usable = true;
  std::string message;  ///< the last solve's report
};

RobustPgoResult optimizePoseGraph(const PoseGraph& graph,
                                  const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                                  const RobustPgoOptions& options = {});

}  // namespace hydra_multi
