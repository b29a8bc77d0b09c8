#include "hydra_multi/sim/trajectory.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace hydra_multi::sim {

std::vector<StampedPose> sampleTrajectory(const std::vector<Eigen::Vector2d>& path, double z,
                                          int64_t start_time_ns, const TrajectoryOptions& options) {
  std::vector<Eigen::Vector3d> path3d;
  for (const Eigen::Vector2d& p : path) path3d.emplace_back(p.x(), p.y(), z);
  return sampleTrajectory(path3d, start_time_ns, options);
}

std::vector<StampedPose> sampleTrajectory(const std::vector<Eigen::Vector3d>& path,
                                          int64_t start_time_ns, const TrajectoryOptions& options) {
  std::vector<StampedPose> keyframes;
  if (path.empty()) return keyframes;
  // Arc-length parametrization of the polyline.
  std::vector<double> arc = {0.0};
  for (size_t i = 1; i < path.size(); ++i)
    arc.push_back(arc.back() + (path[i] - path[i - 1]).norm());
  const double length = arc.back();
  const auto at = [&](double s) {
    const size_t i = static_cast<size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin());
    if (i >= arc.size()) return path.back();
    if (i == 0) return path.front();
    const double t = (s - arc[i - 1]) / std::max(arc[i] - arc[i - 1], 1e-12);
    return Eigen::Vector3d(path[i - 1] + t * (path[i] - path[i - 1]));
  };
  double yaw = 0.0;
  for (double s = 0.0; s <= length + 1e-9; s += options.keyframe_spacing) {
    const Eigen::Vector3d p = at(s);
    // Heading: towards a point half a metre ahead (smooths the grid path's zigzag).
    const Eigen::Vector2d ahead = (at(std::min(s + 0.5, length)) - p).head<2>();
    if (ahead.norm() > 1e-6) yaw = std::atan2(ahead.y(), ahead.x());
    StampedPose pose;
    pose.time_ns = start_time_ns + static_cast<int64_t>(std::llround(s / options.speed * 1e9));
    pose.T_world_body.translation() << p.x(), p.y(), p.z() + options.body_height;
    pose.T_world_body.linear() =
        Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    keyframes.push_back(pose);
  }
  return keyframes;
}

std::vector<Eigen::Isometry3d> simulateOdometry(const std::vector<StampedPose>& truth,
                                                const OdometryNoise& noise) {
  std::vector<Eigen::Isometry3d> odometry;
  if (truth.empty()) return odometry;
  std::mt19937_64 rng(noise.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  odometry.push_back(Eigen::Isometry3d::Identity());
  const double scale_bias = 1.0 + noise.scale_bias_sigma * gauss(rng);
  const double yaw_bias = noise.yaw_bias_sigma * gauss(rng);
  for (size_t k = 1; k < truth.size(); ++k) {
    Eigen::Isometry3d step = truth[k - 1].T_world_body.inverse() * truth[k].T_world_body;
    const double length = step.translation().norm();
    step.translation() *= scale_bias;
    const double scale = std::sqrt(length);
    Vector6d xi;
    for (int i = 0; i < 3; ++i) xi[i] = noise.translation_sigma * scale * gauss(rng);
    xi[3] = noise.roll_pitch_sigma * scale * gauss(rng);
    xi[4] = noise.roll_pitch_sigma * scale * gauss(rng);
    xi[5] = noise.yaw_sigma * scale * gauss(rng) + yaw_bias * length;
    odometry.push_back(odometry.back() * step * expSE3(xi));
  }
  return odometry;
}

}  // namespace hydra_multi::sim
