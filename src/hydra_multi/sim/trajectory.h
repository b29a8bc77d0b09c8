#pragma once
// A robot's true trajectory and its odometry.
//
// Keyframes are taken every `keyframe_spacing` metres along a path driven at `speed`, the body
// facing the direction of travel (x forward, z up). Odometry composes the true relative motions
// with noise, T_odom_k = T_odom_{k-1} * scaled(T_{k-1}^-1 T_k) * exp(xi_k), where
//   - xi_k ~ N(0, diag(sigma^2) * s_k) for a step of length s_k: a random walk whose drift grows
//     with distance, mostly in translation and yaw and slight in roll and pitch;
//   - plus two biases drawn once per robot, as a visual-inertial estimator has them: a scale
//     error of the translation (N(0, scale_bias_sigma)) and a yaw rate per metre
//     (N(0, yaw_bias_sigma)), yaw being unobservable to it. Roll and pitch stay bounded by
//     gravity, hence their small sigma.
// The random walk's heading errors give a lateral error of about yaw_sigma * L^1.5 / sqrt(3) on
// a straight path of length L, the yaw bias b one of b * L^2 / 2; on loops the random part
// largely cancels and the bias does not. The defaults give a final drift of about 2 % of a
// straight 100 m path on average (1.5-3 %, measured by the tests; more over longer paths, the
// bias growing quadratically): the high end of what visual-inertial odometry reports (Kimera-VIO
// and VINS-Mono: about 1 % of the distance travelled), so that on tours that come back to their
// start drift still matters, as it does on the paper's datasets.

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

/// Keyframes along a 3D polyline of floor points (the body body_height above them), e.g. a tour
/// that takes the stairs; the heading follows the path in x-y.
std::vector<StampedPose> sampleTrajectory(const std::vector<Eigen::Vector3d>& path,
                                          int64_t start_time_ns,
                                          const TrajectoryOptions& options = {});

struct OdometryNoise {
  double translation_sigma = 0.01;   ///< per sqrt(m), each axis
  double yaw_sigma = 0.001;          ///< rad per sqrt(m)
  double roll_pitch_sigma = 0.0003;  ///< rad per sqrt(m)
  double scale_bias_sigma = 0.01;    ///< relative scale error, drawn once
  double yaw_bias_sigma = 0.0005;    ///< rad per m of travel, drawn once
  uint64_t seed = 1;
};

/// The odometric poses, in the robot's own frame (its first pose is the identity).
std::vector<Eigen::Isometry3d> simulateOdometry(const std::vector<StampedPose>& truth,
                                                const OdometryNoise& noise);

}  // namespace hydra_multi::sim
