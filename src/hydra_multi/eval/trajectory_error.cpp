#include "hydra_multi/eval/trajectory_error.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

namespace hydra_multi {

ErrorStatistics errorStatistics(std::vector<double> errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  std::sort(errors.begin(), errors.end());
  const double n = static_cast<double>(errors.size());
  const double sum = std::accumulate(errors.begin(), errors.end(), 0.0);
  double sum_sq = 0.0;
  for (const double e : errors) sum_sq += e * e;
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  s.std = std::sqrt(std::max(0.0, sum_sq / n - s.mean * s.mean));
  s.min = errors.front();
  s.max = errors.back();
  const size_t mid = errors.size() / 2;
  s.median = errors.size() % 2 == 1 ? errors[mid] : 0.5 * (errors[mid - 1] + errors[mid]);
  return s;
}

Result<TrajectoryError> absoluteTrajectoryError(const std::vector<Eigen::Vector3d>& estimate,
                                                const std::vector<Eigen::Vector3d>& reference,
                                                bool align) {
  if (estimate.size() != reference.size()) {
    return Error{"ATE: " + std::to_string(estimate.size()) + " estimated positions but " +
                 std::to_string(reference.size()) + " reference positions"};
  }
  if (estimate.size() < 3) return Error{"ATE: fewer than 3 positions"};
  TrajectoryError result;
  if (align) {
    Eigen::Matrix3Xd src(3, estimate.size()), dst(3, reference.size());
    for (size_t i = 0; i < estimate.size(); ++i) {
      src.col(static_cast<long>(i)) = estimate[i];
      dst.col(static_cast<long>(i)) = reference[i];
    }
    const auto alignment = umeyamaAlignment(src, dst, false);
    if (!alignment) return Error{"ATE: the positions are degenerate (collinear) for alignment"};
    result.T_reference_estimate = alignment->T_dst_src;
  }
  std::vector<double> errors(estimate.size());
  for (size_t i = 0; i < estimate.size(); ++i) {
    errors[i] = (result.T_reference_estimate * estimate[i] - reference[i]).norm();
  }
  result.statistics = errorStatistics(std::move(errors));
  return result;
}

Result<std::vector<Eigen::Vector3d>> readKittiPositions(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open"};
  std::vector<Eigen::Vector3d> positions;
  std::string line;
  size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    double m[12];
    std::string extra;
    for (double& v : m) {
      if (!(fields >> v) || !std::isfinite(v)) {
        return Error{path + ":" + std::to_string(line_number) + ": expected 12 finite numbers"};
      }
    }
    if (fields >> extra)
      return Error{path + ":" + std::to_string(line_number) +
                   ": expected 12 numbers, found more ('" + extra + "')"};
    positions.emplace_back(m[3], m[7], m[11]);
  }
  if (positions.empty()) return Error{path + ": no pose (a KITTI file has one 3x4 pose per line)"};
  return positions;
}

Result<StampedPositions> readTumTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open"};
  StampedPositions trajectory;
  std::string line;
  size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    std::string extra;
    for (double& x : v) {
      if (!(fields >> x) || !std::isfinite(x)) {
        return Error{path + ":" + std::to_string(line_number) +
                     ": expected 8 finite numbers (t tx ty tz qx qy qz qw)"};
      }
    }
    if (fields >> extra)
      return Error{path + ":" + std::to_string(line_number) +
                   ": expected 8 numbers (t tx ty tz qx qy qz qw), found more ('" + extra + "')"};
    if (!trajectory.stamps.empty() && v[0] <= trajectory.stamps.back()) {
      return Error{path + ":" + std::to_string(line_number) + ": timestamps must increase"};
    }
    trajectory.stamps.push_back(v[0]);
    trajectory.positions.emplace_back(v[1], v[2], v[3]);
  }
  if (trajectory.stamps.empty())
    return Error{path + ": no pose (a TUM file has one 't tx ty tz qx qy qz qw' per line)"};
  return trajectory;
}

std::vector<std::pair<size_t, size_t>> associateByTime(const std::vector<double>& estimate,
                                                       const std::vector<double>& reference,
                                                       double max_difference) {
  std::vector<std::pair<size_t, size_t>> pairs;
  size_t j = 0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    // Both lists increase: advance to the nearest reference stamp not used yet.
    while (j + 1 < reference.size() &&
           std::abs(reference[j + 1] - estimate[i]) < std::abs(reference[j] - estimate[i])) {
      ++j;
    }
    if (j < reference.size() && std::abs(reference[j] - estimate[i]) <= max_difference) {
      pairs.emplace_back(i, j);
      ++j;
    }
  }
  return pairs;
}

}  // namespace hydra_multi
