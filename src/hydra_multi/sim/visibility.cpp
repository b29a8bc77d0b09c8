#include "hydra_multi/sim/visibility.h"

#include <algorithm>
#include <cmath>

namespace hydra_multi::sim {

bool lineOfSight(const FloorGrid& grid, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  // Sample the segment every quarter cell; a wall cell on it blocks the view.
  const double length = (to - from).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(length / (0.25 * grid.resolution))));
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector2i c = grid.cellOf(from + (to - from) * (double(k) / steps));
    if (!grid.inside(c.x(), c.y()) || grid.wall[grid.index(c.x(), c.y())]) return false;
  }
  return true;
}

std::vector<int> visibleObjects(const World& world, const FreeSpace& space, int floor,
                                const Eigen::Isometry3d& T_world_body, const SensorModel& sensor) {
  std::vector<int> visible;
  if (floor < 0 || static_cast<size_t>(floor) >= space.floors.size()) return visible;
  const FloorGrid& grid = space.floors[static_cast<size_t>(floor)];
  const Eigen::Vector2d eye = T_world_body.translation().head<2>();
  const Eigen::Vector2d forward = T_world_body.linear().col(0).head<2>().normalized();
  const double half_fov = 0.5 * sensor.horizontal_fov_deg * M_PI / 180.0;
  for (const ObjectInstance& object : world.objects) {
    if (world.room(object.room).floor != floor) continue;
    const Eigen::Vector2d to = object.T_world_object.translation().head<2>() - eye;
    const double distance = to.norm();
    if (distance > sensor.range || distance < 1e-6) continue;
    const double angle = std::acos(std::clamp(forward.dot(to / distance), -1.0, 1.0));
    if (angle > half_fov) continue;
    if (lineOfSight(grid, eye, object.T_world_object.translation().head<2>()))
      visible.push_back(object.id);
  }
  return visible;
}

}  // namespace hydra_multi::sim
