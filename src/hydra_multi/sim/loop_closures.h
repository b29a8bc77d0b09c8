#pragma once
// A robot's own (intra-robot) loop closures, as its place-recognition front end would find them,
// emulated from ground truth. At keyframe k, after a cooldown since the last closure, the robot
// looks for an earlier keyframe j (at least `min_time_gap_s` before) that looks the same:
//   - a true revisit: j within `max_distance` and `max_yaw_deg` of k; the measured relative pose
//     is the true one, with noise;
//   - perceptual aliasing: j in another room with the same furniture layout (World::Room::layout)
//     at the corresponding pose in that room's frame; accepted with `aliasing_acceptance`; the
//     measurement is the relative pose of the two poses in their room frames, which is what a
//     registration of the look-alike views returns, and it is wrong;
//   - a gross mistake, with probability `gross_error_share` per closure: the true relative pose
//     corrupted by metres and tens of degrees.
// A look-alike wins when it is closer in pose than the best true revisit and is accepted;
// otherwise the best true revisit, if there is one. Everything is deterministic from the seed.

#include <cstdint>
#include <vector>

#include "hydra_multi/sim/trajectory.h"
#include "hydra_multi/sim/world.h"

namespace hydra_multi::sim {

struct LoopClosureOptions {
  double min_time_gap_s = 30.0;
  double cooldown_s = 5.0;  ///< at most one closure per this much time
  double max_distance = 1.0;
  double max_yaw_deg = 30.0;
  double aliasing_acceptance = 0.05;
  double gross_error_share = 0.03;
  double translation_sigma = 0.03;  ///< noise of a measured closure (m)
  double rotation_sigma_deg = 1.0;
  uint64_t seed = 1;
};

struct SimulatedLoopClosure {
  size_t from = 0, to = 0;  ///< keyframe indices, from < to
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  bool correct = true;
  enum class Kind : uint8_t { kRevisit, kAliasing, kGrossError } kind = Kind::kRevisit;
};

/// `rooms`: the true room of every keyframe (-1 in doorways and on stairs).
std::vector<SimulatedLoopClosure> simulateLoopClosures(const World& world,
                                                       const std::vector<StampedPose>& truth,
                                                       const std::vector<int>& rooms,
                                                       const LoopClosureOptions& options = {});

}  // namespace hydra_multi::sim
