#pragma once
// The objects a semantic robot detects (Hydra's object layer, emulated from ground truth): an
// object seen (visibility.h) from at least `min_views` keyframes is detected, unless missed;
// its label may be confused with a similar class; its centroid carries position noise and its box
// the true extents around it. Misses and confusions are drawn once per object, deterministically
// from the seed, so the same robot makes the same mistakes on every run.

#include <cstdint>
#include <vector>

#include "hydra_multi/sim/trajectory.h"
#include "hydra_multi/sim/visibility.h"

namespace hydra_multi::sim {

struct DetectionOptions {
  int min_views = 2;
  double miss_probability = 0.1;
  double confusion_probability = 0.1;
  double position_sigma = 0.05;  ///< m, each axis
  uint64_t seed = 1;
};

struct DetectedObject {
  int true_id = 0;
  uint32_t label = 0;  ///< what the robot believes (may be confused)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< world frame, noisy
  BoundingBox box;                                     ///< axis-aligned, world frame
  size_t first_keyframe = 0;  ///< index of the keyframe that completed the detection
};

/// The label a class is confused with, or the label itself when it has no look-alike.
uint32_t confusableLabel(uint32_t label);

std::vector<DetectedObject> detectObjects(const World& world, const FreeSpace& space, int floor,
                                          const std::vector<StampedPose>& keyframes,
                                          const SensorModel& sensor = {},
                                          const DetectionOptions& options = {});

/// The same for a robot that changes floors: `floors` holds the floor of every keyframe.
std::vector<DetectedObject> detectObjects(const World& world, const FreeSpace& space,
                                          const std::vector<int>& floors,
                                          const std::vector<StampedPose>& keyframes,
                                          const SensorModel& sensor = {},
                                          const DetectionOptions& options = {});

}  // namespace hydra_multi::sim
