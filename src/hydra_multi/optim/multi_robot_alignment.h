#pragma once
// The initial alignment of robot frames (paper III-B, eq. (1)-(2); Kimera-Multi):
//   for every inter-robot loop closure Z between a_i (robot A) and b_j (robot B),
//     T_A_B,ij = T_A_ai * Z_ai_bj * (T_B_bj)^-1                                        eq. (1)
//   per robot pair, robust pose averaging of those estimates with GNC-TLS             eq. (2)
//   a pair counts with at least k inliers (k = 5), each pair of keyframes once (a frontend finds
//   one match again from later keyframes: not new evidence); a spanning tree over robots prefers
//   the pairs with the most inliers; transforms are chained to the root robot's frame (the global
//   frame).

#include <map>
#include <optional>
#include <unordered_map>
#include <vector>

#include "hydra_multi/optim/pose_averaging.h"
#include "hydra_multi/optim/pose_graph.h"

namespace hydra_multi {

struct MultiRobotAlignmentOptions {
  size_t min_inliers = 5;  ///< k of the paper
  /// Sigma^-1 of eq. (2). The estimates of eq. (1) carry the odometry drift of both robots, so
  /// Sigma is loose: 1 m and 0.1 rad standard deviations by default.
  PoseAveragingOptions averaging = [] {
    PoseAveragingOptions options;
    options.information.setZero();
    options.information.diagonal() << 1.0, 1.0, 1.0, 100.0, 100.0, 100.0;
    return options;
  }();
  /// Threads that average the robot pairs (eq. (2)); each pair's average is its own, so the
  /// result does not depend on them.
  size_t threads = 2;
};

struct RobotPairAlignment {
  size_t robot_a = 0, robot_b = 0;
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();
  size_t loop_closures = 0;
  size_t inliers = 0;  ///< keyframe pairs among the inlier loop closures
  bool in_tree = false;
};

struct MultiRobotAlignment {
  /// T_world_robot per robot; nullopt for robots the tree does not reach.
  std::vector<std::optional<Eigen::Isometry3d>> T_world_robot;
  std::vector<RobotPairAlignment> pairs;
  /// Per inter-robot edge given: whether its pair's averaging kept it.
  std::vector<bool> edge_inlier;
  size_t numAligned() const;
};

/// `local_poses`: every node's pose in its own robot's frame; `robot_of`: every node's robot
/// (0..num_robots-1); `inter_robot_edges`: loop closures whose ends belong to different robots.
/// The root robot defines the global frame. `edge_support` (empty: 1 each) weighs each edge in
/// its pair's maximum consensus (robustPoseAverage). `consensus` (when given) keeps each robot
/// pair's consensus tests for the next call (ConsensusCache: the same result as without).
MultiRobotAlignment alignRobotFrames(
    size_t num_robots, const std::map<NodeId, Eigen::Isometry3d>& local_poses,
    const std::unordered_map<NodeId, size_t>& robot_of,
    const std::vector<PoseGraphEdge>& inter_robot_edges, size_t root = 0,
    const MultiRobotAlignmentOptions& options = {}, const std::vector<double>& edge_support = {},
    std::map<std::pair<size_t, size_t>, ConsensusCache>* consensus = nullptr);

}  // namespace hydra_multi
