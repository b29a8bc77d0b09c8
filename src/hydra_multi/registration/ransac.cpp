#include "hydra_multi/registration/ransac.h"

#include <cmath>
#include <random>

#include "hydra_multi/registration/closed_form.h"

namespace hydra_multi {
namespace {

std::vector<size_t> inliersOf(const Eigen::Isometry3d& T, const std::vector<Eigen::Vector3d>& src,
                              const std::vector<Eigen::Vector3d>& dst, double threshold) {
  std::vector<size_t> inliers;
  for (size_t i = 0; i < src.size(); ++i) {
    if ((T * src[i] - dst[i]).norm() <= threshold) inliers.push_back(i);
  }
  return inliers;
}

}  // namespace

Result<RegistrationResult> ransacRegistration(const std::vector<Eigen::Vector3d>& source,
                                              const std::vector<Eigen::Vector3d>& target,
                                              const RansacOptions& options) {
  if (source.size() != target.size())
    return Error{"ransac: " + std::to_string(source.size()) + " source and " +
                 std::to_string(target.size()) + " target points"};
  const size_t n = source.size();
  if (n < std::max<size_t>(3, options.min_inliers))
    return Error{"ransac: " + std::to_string(n) + " correspondences, fewer than " +
                 std::to_string(std::max<size_t>(3, options.min_inliers))};
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<size_t> pick(0, n - 1);
  std::vector<size_t> best;
  Eigen::Isometry3d best_T = Eigen::Isometry3d::Identity();
  int needed = options.max_iterations;
  for (int iteration = 0; iteration < needed; ++iteration) {
    size_t a = pick(rng), b = pick(rng), c = pick(rng);
    if (a == b || b == c || a == c) continue;
    const auto T = weightedRigidAlignment({source[a], source[b], source[c]},
                                          {target[a], target[b], target[c]});
    if (!T) continue;
    std::vector<size_t> inliers = inliersOf(*T, source, target, options.inlier_threshold);
    if (inliers.size() <= best.size()) continue;
    best = std::move(inliers);
    best_T = *T;
    // Iterations for `confidence` of drawing one all-inlier sample at this inlier ratio.
    const double ratio = double(best.size()) / double(n);
    const double all_in = ratio * ratio * ratio;
    if (all_in >= 1.0 - 1e-12) break;
    const double k = std::log(1.0 - options.confidence) / std::log(1.0 - all_in);
    needed = std::min(options.max_iterations, static_cast<int>(std::ceil(k)) + iteration + 1);
  }
  if (best.size() < options.min_inliers)
    return Error{"ransac: best hypothesis has " + std::to_string(best.size()) +
                 " inliers, fewer than " + std::to_string(options.min_inliers)};
  // Refit on the inliers, then take the inliers of the refit (twice settles it).
  RegistrationResult result;
  result.T_target_source = best_T;
  result.inliers = best;
  for (int round = 0; round < 2; ++round) {
    std::vector<Eigen::Vector3d> src, dst;
    for (const size_t i : result.inliers) {
      src.push_back(source[i]);
      dst.push_back(target[i]);
    }
    const auto T = weightedRigidAlignment(src, dst);
    if (!T) break;
    std::vector<size_t> inliers = inliersOf(*T, source, target, options.inlier_threshold);
    if (inliers.size() < options.min_inliers) break;
    result.T_target_source = *T;
    result.inliers = std::move(inliers);
  }
  double sum = 0.0;
  for (const size_t i : result.inliers)
    sum += (result.T_target_source * source[i] - target[i]).squaredNorm();
  result.rmse = std::sqrt(sum / double(result.inliers.size()));
  return result;
}

}  // namespace hydra_multi
