#pragma once
// What a registration returns.

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace hydra_multi {

struct RegistrationResult {
  Eigen::Isometry3d T_target_source = Eigen::Isometry3d::Identity();
  std::vector<size_t> inliers;  ///< indices of the correspondences (or source points) kept
  double rmse = 0.0;            ///< over the inliers (m)
};

}  // namespace hydra_multi
