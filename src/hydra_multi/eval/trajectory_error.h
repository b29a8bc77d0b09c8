#pragma once
// Absolute trajectory error (paper IV: ATE): the positions of an estimate are aligned to the
// reference by the SE(3) transform that fits them best (Umeyama, no scale), then the distances of
// corresponding positions are summarized. Matches the evaluation tool whose KITTI figures are in
// data/README.md.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/core/se3.h"

namespace hydra_multi {

struct ErrorStatistics {
  size_t count = 0;
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
};

/// Statistics of a list of errors (std is the population standard deviation).
ErrorStatistics errorStatistics(std::vector<double> errors);

struct TrajectoryError {
  ErrorStatistics statistics;
  Eigen::Isometry3d T_reference_estimate = Eigen::Isometry3d::Identity();  ///< the alignment
};

/// ATE of corresponding positions; `align` false compares them as they are. Fails on a size
/// mismatch, fewer than 3 positions, or a degenerate alignment.
Result<TrajectoryError> absoluteTrajectoryError(const std::vector<Eigen::Vector3d>& estimate,
                                                const std::vector<Eigen::Vector3d>& reference,
                                                bool align = true);

/// The positions of a KITTI pose file (one 3x4 row-major matrix per line).
Result<std::vector<Eigen::Vector3d>> readKittiPositions(const std::string& path);

/// A trajectory with timestamps (TUM format: "t tx ty tz qx qy qz qw" per line; '#' comments).
struct StampedPositions {
  std::vector<double> stamps;
  std::vector<Eigen::Vector3d> positions;
};
Result<StampedPositions> readTumTrajectory(const std::string& path);

/// Pairs of indices (estimate, reference) whose stamps differ by at most `max_difference`, each
/// estimate with its nearest reference stamp (the earlier one on a tie), each reference used once,
/// in time order.
std::vector<std::pair<size_t, size_t>> associateByTime(const std::vector<double>& estimate,
                                                       const std::vector<double>& reference,
                                                       double max_difference);

}  // namespace hydra_multi
