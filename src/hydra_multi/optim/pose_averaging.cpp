#include "hydra_multi/optim/pose_averaging.h"

#include <algorithm>
#include <string>

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
                                      const PoseAveragingOptions& options,
                                      const std::vector<double>& support, ConsensusCache* cache) {
  if (estimates.empty()) return Error{"pose averaging: no estimates"};
  if (!support.empty() && support.size() != estimates.size())
    return Error{"pose averaging: " + std::to_string(support.size()) + " supports for " +
                 std::to_string(estimates.size()) + " estimates"};
  const bool weighted =
      std::any_of(support.begin(), support.end(), [](double w) { return w > 0.0; });
  PoseAverage average;
  const auto residual = [&](const Eigen::Isometry3d& X, const Eigen::Isometry3d& estimate) {
    const Vector6d e = logSE3(relativePose(X, estimate));
    return e.dot(options.information * e);
  };
  if (options.consensus) {
    const double c2 = options.gnc.thresholdSq();
    // Per estimate, the others within the threshold (kept from the cache while it holds).
    ConsensusCache local;
    ConsensusCache& kept = cache != nullptr ? *cache : local;
    const size_t n = estimates.size();
    size_t known = std::min(kept.estimates.size(), n);
    if (kept.information != options.information || kept.threshold_sq != c2 ||
        kept.estimates.size() > n)
      known = 0;
    for (size_t i = 0; i < known; ++i) {
      if (kept.estimates[i].matrix() != estimates[i].matrix()) {
        known = 0;
        break;
      }
    }
    kept.within.resize(known);
    kept.within.resize(n);
    kept.tested = 0;
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = i < known ? known : 0; j < n; ++j) {
        const double r2 = residual(estimates[i], estimates[j]);
        ++kept.tested;
        if (r2 <= c2) kept.within[i].emplace_back(static_cast<uint32_t>(j), r2);
      }
    }
    kept.estimates = estimates;
    kept.information = options.information;
    kept.threshold_sq = c2;
    // The estimate with the most support within the threshold (ties: the most neighbours, then
    // the smaller spread).
    size_t best = 0, best_count = 0;
    double best_support = -1.0, best_spread = 0.0;
    for (size_t i = 0; i < n; ++i) {
      size_t count = 0;
      double spread = 0.0, sum = 0.0;
      for (const auto& [j, r2] : kept.within[i]) {
        ++count;
        spread += r2;
        sum += weighted ? support[j] : 1.0;
      }
      if (sum > best_support ||
          (sum == best_support &&
           (count > best_count || (count == best_count && spread < best_spread)))) {
        best = i;
        best_count = count;
        best_support = sum;
        best_spread = spread;
      }
    }
    Eigen::Isometry3d current = estimates[best];
    std::vector<double> weights(estimates.size(), 0.0);
    for (int iteration = 0; iteration < 50; ++iteration) {
      std::vector<double> next(estimates.size());
      for (size_t k = 0; k < estimates.size(); ++k)
        next[k] = residual(current, estimates[k]) <= c2 ? 1.0 : 0.0;
      if (next == weights) break;
      weights = next;
      auto X =
          weightedPoseAverage(estimates, weights, current, options.max_gauss_newton_iterations);
      if (!X) break;
      current = X.value();
    }
    average.T = current;
    average.gnc.weights = weights;
    average.gnc.stop_reason = "consensus";
    for (const double w : weights) {
      average.inliers.push_back(w > 0.5);
      average.num_inliers += w > 0.5;
    }
    average.gnc.inliers = average.inliers;
    average.gnc.num_inliers = average.num_inliers;
    return average;
  }
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
