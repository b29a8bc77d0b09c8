#pragma once
// Robust pose averaging, eq. (2) of the paper:
//   X* = argmin_{X in SE(3)} sum_k rho_TLS( || X boxminus X_k ||_Sigma )
// with X boxminus X_k = log(X^-1 X_k) and one fixed covariance Sigma. Used for the relative frame
// of two robots from the per-loop-closure estimates of eq. (1):
//   T_A_B,ij = T_A_ai * Z_ai_bj * (T_B_bj)^-1.
// The weighted problem is solved by Gauss-Newton on SE(3); with one Sigma shared by all
// measurements the step is the weighted mean of the tangent errors, delta = sum w_k e_k / sum w_k
// (the Jacobian of log is taken as identity, exact at the solution of consistent measurements).
// GNC (gnc.h) supplies the TLS weights.

#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/core/se3.h"
#include "hydra_multi/optim/gnc.h"

namespace hydra_multi {

struct PoseAveragingOptions {
  Matrix6d information = Matrix6d::Identity();  ///< Sigma^-1, order: translation, rotation
  GncOptions gnc;
  int max_gauss_newton_iterations = 50;
  /// Maximum consensus instead of GNC from the least-squares mean: start at the estimate with
  /// the most others within the inlier threshold, then alternate the TLS inlier set (within the
  /// threshold of the average) and the average of that set until the set is stable. GNC from the
  /// mean follows the bulk of the estimates; when most of them are wrong (look-alike rooms give
  /// several consistent wrong clusters) the largest consistent cluster is the right one more
  /// often than the mean's basin is.
  bool consensus = false;
};

struct PoseAverage {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  std::vector<bool> inliers;
  size_t num_inliers = 0;
  GncResult gnc;
};

/// The weighted average (Gauss-Newton from `start`); fails when every weight is zero.
Result<Eigen::Isometry3d> weightedPoseAverage(const std::vector<Eigen::Isometry3d>& estimates,
                                              const std::vector<double>& weights,
                                              const Eigen::Isometry3d& start, int max_iterations);

/// The maximum consensus's pairwise test kept from call to call on a list of estimates that grows
/// (a robot pair's loop closures, round after round): the estimates as last seen and, per
/// estimate, the others within the threshold of it (index, squared residual), in index order.
/// Estimates appended since are tested against all; an earlier estimate changed (or other options)
/// drops what was kept. The same result as without.
struct ConsensusCache {
  std::vector<Eigen::Isometry3d> estimates;
  std::vector<std::vector<std::pair<uint32_t, double>>> within;
  Matrix6d information = Matrix6d::Zero();
  double threshold_sq = 0.0;
  size_t tested = 0;  ///< pairs tested by the last call
};

/// eq. (2) with GNC-TLS (or maximum consensus, see options); fails with no estimates.
/// `support` (maximum consensus only; empty: 1 each) is what each estimate is worth: the start is
/// the estimate whose neighbours within the threshold have the most support in sum (ties: the
/// most neighbours, then the smaller spread). Every support zero counts as none given. `cache`
/// (maximum consensus only) is read and updated.
Result<PoseAverage> robustPoseAverage(const std::vector<Eigen::Isometry3d>& estimates,
                                      const PoseAveragingOptions& options = {},
                                      const std::vector<double>& support = {},
                                      ConsensusCache* cache = nullptr);

}  // namespace hydra_multi
