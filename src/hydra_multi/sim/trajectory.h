#pragma once
// A robot's true trajectory and its odometry.
//
// Keyframes are taken every `keyframe_spacing` metres along a path driven at `speed`, the body
// facing the direction of travel (x forward, z up). Odometry composes the true relative motions
// with noise, T_odom_k = T_odom_{k-1} * (T_{k-1}^-1 T_k) * exp(xi_k), xi_k ~ N(0, diag(sigma^2) *
// s_k) for a step of length s_k: a random walk whose drift grows with distance, mostly in
// translation and yaw and slight in roll and pitch, as with visual-inertial odometry. Heading
// errors dominate: on a straight path of length L the lateral error grows like yaw_sigma * L^1.5 /
// sqrt(3). The default sigmas give a final drift of 1-2 % of a straight path's length (measured by
// the tests), the order usually reported for visual-inertial odometry; on loops much of it cancels
// at the end.

#include <cstdint>
#include <vector>

#include "hydra_multi/core/se3.h"

namespace hydra_multi::sim {

struct StampedPose {
  int64_t time_ns = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
};

struct TrajectoryOptions {
  double speed = 0.5;             ///< m/s
  double keyframe_spacing = 0.5;  ///< m between keyframes
  double body_height = 1.0;       ///< sensor height above the floor (m)
};

/// Keyframes along a polyline in x-y at floor height `z` (the body at z + body_height).
std::vector<StampedPose> sampleTrajectory(const std::vector<Eigen::Vector2d>& path, double z,
                                          int64_t start_time_ns,
                                          const TrajectoryOptions& options = {});

struct OdometryNoise {
  double translation_sigma = 0.01;   ///< per sqrt(m), each axis
  double yaw_sigma = 0.0015;         ///< rad per sqrt(m)
  double roll_pitch_sigma = 0.0003;  ///< rad per sqrt(m)
  uint64_t seed = 1;
};

/// The odometric poses, in the robot's own frame (its first pose is the identity).
std::vector<Eigen::Isometry3d> simulateOdometry(const std::vector<StampedPose>& truth,
                                                const OdometryNoise& noise);

}  // namespace hydra_multi::sim
