#pragma once
// Iterative closest point, for aligning the mesh vertices of two objects before merging them:
// each source point (moved by the current estimate) is paired with its nearest target point
// (nanoflann KD-tree, core/nearest_neighbors.h) if it is within max_correspondence_distance;
//   point to point  the pairs' closed-form alignment (closed_form.h) is the new estimate;
//   point to plane  one Gauss-Newton step on sum_i (n_i . (T s_i - d_i))^2 with the target's
//                   normals n_i (from the covariance of its k nearest neighbours), linearized
//                   about the estimate with the rotation about the paired points' centroid c:
//                   T <- (p -> R(omega)(p - c) + c + t) * T (Low 2004); lightly damped, so a
//                   direction the planes leave free (a flat top sliding on itself) stays put.
// Stops when an update moves less than the convergence bounds or after max_iterations.

#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/registration/registration_result.h"

namespace hydra_multi {

struct IcpOptions {
  enum class Metric { kPointToPoint, kPointToPlane };
  Metric metric = Metric::kPointToPlane;
  double max_correspondence_distance = 0.5;  ///< m
  int max_iterations = 50;
  double translation_tolerance = 1e-5;  ///< m per iteration
  double rotation_tolerance = 1e-5;     ///< rad per iteration
  size_t normal_neighbors = 8;          ///< point to plane: neighbours for a normal
  size_t min_correspondences = 6;
};

struct IcpResult : RegistrationResult {
  int iterations = 0;
  bool converged = false;
};

/// p_target = T * p_source, starting from `initial`. `inliers` are the source points paired at
/// the end.
Result<IcpResult> icp(const std::vector<Eigen::Vector3d>& source,
                      const std::vector<Eigen::Vector3d>& target,
                      const Eigen::Isometry3d& initial = Eigen::Isometry3d::Identity(),
                      const IcpOptions& options = {});

}  // namespace hydra_multi
