#pragma once
// Robust registration of putative correspondences with most of them wrong, TEASER++-style (Yang,
// Shi, Carlone, T-RO 2020), for objects: every same-label pair of two robots' objects is a
// putative correspondence.
//   1. pairwise consistency: correspondences i and j agree when rigid motion could map both,
//      | ||s_i - s_j|| - ||d_i - d_j|| | <= 2 * noise_bound (distances are invariant);
//   2. the maximum clique of that graph (max_clique.h) keeps the mutually consistent ones;
//   3. GNC with truncated least squares (optim/gnc.h) over the clique, each weighted solve a
//      closed-form weighted alignment (closed_form.h): residuals above noise_bound are outliers;
//   4. at least min_inliers inliers (Hydra-Multi: 5), refit on them.
// A coordinate that is not finite is an error naming its correspondence.

#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/registration/registration_result.h"

namespace hydra_multi {

struct TlsRegistrationOptions {
  double noise_bound = 0.3;  ///< m: the largest residual of a correct correspondence
  size_t min_inliers = 5;
  size_t max_clique_steps = 200000;
};

/// p_target = T * p_source for the putative correspondences source[i] <-> target[i].
Result<RegistrationResult> tlsRegistration(const std::vector<Eigen::Vector3d>& source,
                                           const std::vector<Eigen::Vector3d>& target,
                                           const TlsRegistrationOptions& options = {});

/// The rival of a registration `best` of these correspondences: the best registration of the
/// correspondences that are not its inliers (indices into source/target). In a row of look-alike
/// rooms the same objects register once per room shift, each with about as many inliers; a rival
/// far from `best` with nearly its inliers makes `best` ambiguous.
Result<RegistrationResult> tlsRivalRegistration(const std::vector<Eigen::Vector3d>& source,
                                                const std::vector<Eigen::Vector3d>& target,
                                                const RegistrationResult& best,
                                                const TlsRegistrationOptions& options = {});

}  // namespace hydra_multi
