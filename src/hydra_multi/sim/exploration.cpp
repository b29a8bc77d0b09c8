#include "hydra_multi/sim/exploration.h"

#include <string>

namespace hydra_multi::sim {

Result<Eigen::Vector2d> roomStandpoint(const FloorGrid& grid, int room) {
  double best = -1.0;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  for (int y = 0; y < grid.height; ++y) {
    for (int x = 0; x < grid.width; ++x) {
      const size_t i = grid.index(x, y);
      if (grid.room[i] == room && grid.clearance[i] > best) {
        best = grid.clearance[i];
        point = grid.cellCenter(x, y);
      }
    }
  }
  if (best < 0.0) return Error{"room " + std::to_string(room) + " has no free cell on this floor"};
  return point;
}

Result<std::vector<Eigen::Vector2d>> planRoomTour(const World& world, const FloorGrid& grid,
                                                  const Eigen::Vector2d& start,
                                                  const std::vector<int>& rooms,
                                                  const PathPlannerOptions& options) {
  std::vector<Eigen::Vector2d> tour = {start};
  const auto driveTo = [&](const Eigen::Vector2d& goal) -> Status {
    auto leg = planPath(grid, tour.back(), goal, options);
    if (!leg) return Error{leg.error()};
    tour.insert(tour.end(), leg.value().begin() + 1, leg.value().end());
    return Status::Ok();
  };
  for (const int room_id : rooms) {
    if (room_id < 0 || static_cast<size_t>(room_id) >= world.rooms.size()) {
      return Error{"tour: no room " + std::to_string(room_id)};
    }
    auto centre = roomStandpoint(grid, room_id);
    if (!centre) return Error{"tour: " + centre.error()};
    if (Status s = driveTo(centre.value()); !s)
      return Error{"tour to room " + std::to_string(room_id) + ": " + s.message()};
    // Look around: the quarter points of the room that are free enough, then back to the centre.
    const Rect& f = world.room(room_id).footprint;
    for (const Eigen::Vector2d& corner :
         {Eigen::Vector2d(0.25, 0.25), Eigen::Vector2d(0.75, 0.25), Eigen::Vector2d(0.75, 0.75),
          Eigen::Vector2d(0.25, 0.75)}) {
      const Eigen::Vector2d p = f.min + corner.cwiseProduct(f.size());
      const Eigen::Vector2i c = grid.cellOf(p);
      if (!grid.inside(c.x(), c.y()) || grid.occupied[grid.index(c.x(), c.y())] ||
          grid.clearance[grid.index(c.x(), c.y())] < options.robot_radius) {
        continue;  // furniture there: skip this look-out
      }
      if (!driveTo(p)) continue;  // unreachable look-out: skip it
    }
    if (Status s = driveTo(centre.value()); !s)
      return Error{"tour in room " + std::to_string(room_id) + ": " + s.message()};
  }
  return tour;
}

}  // namespace hydra_multi::sim
