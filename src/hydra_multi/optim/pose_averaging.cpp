#include "hydra_multi/optim/pose_averaging.h"

namespace hydra_multi {

Result<Eigen::Isometry3d> weightedPoseAverage(const std::vector<Eigen::Isometry3d>& estimates,
                                              const std::vector<double>& weights,
                                              const Eigen::Isometry3d& start, int max_iterations) {
  double total = 0.0;
  for (const double w : weights) total += w;
  if (total <= 0.0) return Error{"pose averaging: every weight is zero"};
  Eigen::Isometry3d X = start;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    Vector6d delta = Vector6d::Zero();
    for (size_t k = 0; k < estimates.size(); ++k) {
      if (weights[k] > 0.0) delta += weights[k] * logSE3(relativePose(X, estimates[k]));
    }
    delta /= total;
    X = X * expSE3(delta);
    if (delta.norm() < 1e-12) break;
  }
  return X;
}

Result<PoseAverage> robustPoseAverage(const std::vector<Eigen::Isometry3d>& estimates,
                                      const PoseAveragingOptions& options) {
  if (estimates.empty()) return Error{"pose averaging: no estimates"};
  PoseAverage average;
  // Warm start: each weighted solve starts from the previous average.
  Eigen::Isometry3d current = estimates.front();
  const auto solve = [&](const std::vector<double>& weights) {
    auto X = weightedPoseAverage(estimates, weights, current, options.max_gauss_newton_iterations);
    if (X) current = X.value();
    WeightedSolution solution;
    solution.squared_residuals.resize(estimates.size());
    for (size_t k = 0; k < estimates.size(); ++k) {
      const Vector6d e = logSE3(relativePose(current, estimates[k]));
      solution.squared_residuals[k] = e.dot(options.information * e);
      solution.cost += weights[k] * solution.squared_residuals[k];
    }
    return solution;
  };
  average.gnc = runGnc(estimates.size(), solve, options.gnc);
  average.T = current;
  average.inliers = average.gnc.inliers;
  average.num_inliers = average.gnc.num_inliers;
  return average;
}

}  // namespace hydra_multi
