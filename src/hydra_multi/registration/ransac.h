#pragma once
// RANSAC over minimal 3-point samples for putative correspondences that are mostly wrong (visual
// keypoints matched by word id): each sample's closed-form transform is scored by the number of
// correspondences it brings within `inlier_threshold`; the best hypothesis is refit on its inliers
// (closed_form.h). The number of iterations adapts to the best inlier ratio so far for the wanted
// confidence, up to max_iterations. Deterministic from the seed.

#include <cstdint>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/registration/registration_result.h"

namespace hydra_multi {

struct RansacOptions {
  double inlier_threshold = 0.2;  ///< m
  int max_iterations = 2000;
  double confidence = 0.999;
  size_t min_inliers = 8;  ///< fewer: the registration fails
  uint64_t seed = 1;
};

/// p_target = T * p_source for the correspondences source[i] <-> target[i].
Result<RegistrationResult> ransacRegistration(const std::vector<Eigen::Vector3d>& source,
                                              const std::vector<Eigen::Vector3d>& target,
                                              const RansacOptions& options = {});

}  // namespace hydra_multi
