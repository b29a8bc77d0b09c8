// `hydra-multi ate --est FILE --gt FILE [--format kitti|tum] [--json]`: absolute trajectory error
// after an SE(3) Umeyama alignment (KITTI: pose per line; TUM: associated by timestamp).

#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/eval/trajectory_error.h"

namespace hydra_multi::apps {

int runAte(const AteOptions& o) {
  std::vector<Eigen::Vector3d> estimate, reference;
  if (o.format == "kitti") {
    auto est = readKittiPositions(o.estimate);
    if (!est) return fail(est.error());
    auto gt = readKittiPositions(o.reference);
    if (!gt) return fail(gt.error());
    if (est.value().size() != gt.value().size()) {
      return fail("KITTI files pair poses by line: " + o.estimate + " has " +
                  std::to_string(est.value().size()) + ", " + o.reference + " has " +
                  std::to_string(gt.value().size()));
    }
    estimate = std::move(est).value();
    reference = std::move(gt).value();
  } else if (o.format == "tum") {
    auto est = readTumTrajectory(o.estimate);
    if (!est) return fail(est.error());
    auto gt = readTumTrajectory(o.reference);
    if (!gt) return fail(gt.error());
    for (const auto& [i, j] :
         associateByTime(est.value().stamps, gt.value().stamps, o.max_time_difference)) {
      estimate.push_back(est.value().positions[i]);
      reference.push_back(gt.value().positions[j]);
    }
    // Poses without a partner are not scored: say how many.
    if (estimate.size() < est.value().stamps.size())
      std::cerr << "ate: " << est.value().stamps.size() - estimate.size() << " of "
                << est.value().stamps.size() << " poses of " << o.estimate
                << " have no reference pose within " << o.max_time_difference
                << " s; scored over the other " << estimate.size() << "\n";
  } else {
    return fail("--format must be kitti or tum, not '" + o.format + "'");
  }
  auto ate = absoluteTrajectoryError(estimate, reference);
  if (!ate) return fail(o.estimate + " against " + o.reference + ": " + ate.error());
  const ErrorStatistics& s = ate.value().statistics;
  if (o.json) {
    const nlohmann::ordered_json j = {{"ate_rmse_m", s.rmse},     {"ate_mean_m", s.mean},
                                      {"ate_median_m", s.median}, {"ate_std_m", s.std},
                                      {"ate_min_m", s.min},       {"ate_max_m", s.max},
                                      {"pairs", s.count}};
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::cout << std::fixed << std::setprecision(6) << "ATE over " << s.count
            << " pose pairs (SE(3) alignment)\n"
            << "  rmse   " << s.rmse << " m\n  mean   " << s.mean << " m\n  median " << s.median
            << " m\n  std    " << s.std << " m\n  min    " << s.min << " m\n  max    " << s.max
            << " m\n";
  return 0;
}

}  // namespace hydra_multi::apps
