#pragma once
// Closed-form rigid registration of corresponding points (Horn 1987 / Umeyama 1991), weighted:
// the rotation and translation minimizing sum_i w_i || dst_i - (R src_i + t) ||^2. The weighted
// centroids give t once R is known; R comes from the SVD of the weighted cross-covariance,
// projected onto SO(3) (no reflection). Every robust estimator of this module solves its inner
// problems with it.

#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace hydra_multi {

/// Weighted least-squares rigid transform mapping src onto dst (p_dst = T * p_src). nullopt with
/// fewer than 3 points of positive weight, a size mismatch, or a degenerate (collinear) set.
std::optional<Eigen::Isometry3d> weightedRigidAlignment(const std::vector<Eigen::Vector3d>& src,
                                                        const std::vector<Eigen::Vector3d>& dst,
                                                        const std::vector<double>& weights = {});

}  // namespace hydra_multi
