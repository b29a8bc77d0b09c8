#pragma once
// What a robot's camera sees of the world's objects: an object is observed from a body pose when
// its centre is within the sensor's range and horizontal field of view and no wall cell lies on
// the straight line to it (doors are open; furniture does not hide furniture, which stands lower
// than the camera).

#include <vector>

#include "hydra_multi/sim/free_space.h"

namespace hydra_multi::sim {

struct SensorModel {
  double range = 5.0;                ///< m
  double horizontal_fov_deg = 90.0;  ///< full angle, about the body's x axis
};

/// Whether the segment between two points of a floor crosses no wall cell.
bool lineOfSight(const FloorGrid& grid, const Eigen::Vector2d& from, const Eigen::Vector2d& to);

/// Ids of the objects observed from the pose (body x forward, on floor `floor`).
std::vector<int> visibleObjects(const World& world, const FreeSpace& space, int floor,
                                const Eigen::Isometry3d& T_world_body,
                                const SensorModel& sensor = {});

}  // namespace hydra_multi::sim
