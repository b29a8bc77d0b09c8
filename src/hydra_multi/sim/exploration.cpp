#include "hydra_multi/sim/exploration.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

namespace hydra_multi::sim {

Result<Eigen::Vector2d> roomStandpoint(const FloorGrid& grid, int room,
                                       const std::optional<Eigen::Vector2d>& reachable_from,
                                       double robot_radius) {
  std::vector<uint8_t> reached;
  if (reachable_from) {
    // Flood fill over the cells the robot fits in, 8-connected as the planner drives.
    const auto fits = [&](int x, int y) {
      return grid.inside(x, y) && !grid.occupied[grid.index(x, y)] &&
             grid.clearance[grid.index(x, y)] >= robot_radius;
    };
    reached.assign(grid.occupied.size(), 0);
    const Eigen::Vector2i seed = grid.cellOf(*reachable_from);
    std::deque<Eigen::Vector2i> queue;
    if (fits(seed.x(), seed.y())) {
      reached[grid.index(seed.x(), seed.y())] = 1;
      queue.push_back(seed);
    }
    while (!queue.empty()) {
      const Eigen::Vector2i c = queue.front();
      queue.pop_front();
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = c.x() + dx, y = c.y() + dy;
          if (!fits(x, y) || reached[grid.index(x, y)]) continue;
          reached[grid.index(x, y)] = 1;
          queue.emplace_back(x, y);
        }
      }
    }
  }
  double best = -1.0;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  for (int y = 0; y < grid.height; ++y) {
    for (int x = 0; x < grid.width; ++x) {
      const size_t i = grid.index(x, y);
      if (grid.room[i] == room && grid.clearance[i] > best && (reached.empty() || reached[i])) {
        best = grid.clearance[i];
        point = grid.cellCenter(x, y);
      }
    }
  }
  if (best < 0.0) {
    return Error{"room " + std::to_string(room) + " has no free cell" +
                 (reachable_from ? " reachable" : "") + " on this floor"};
  }
  return point;
}

namespace {

// Look-out points of a room in a loop: a grid about 4 m apart (2 x 2 at least), serpentine.
std::vector<Eigen::Vector2d> lookouts(const Rect& f) {
  const int nx = std::max(2, static_cast<int>(std::lround(f.size().x() / 4.0)));
  const int ny = std::max(2, static_cast<int>(std::lround(f.size().y() / 4.0)));
  std::vector<Eigen::Vector2d> points;
  for (int j = 0; j < ny; ++j) {
    for (int k = 0; k < nx; ++k) {
      const int i = j % 2 == 0 ? k : nx - 1 - k;
      points.push_back(f.min +
                       Eigen::Vector2d((i + 0.5) / nx, (j + 0.5) / ny).cwiseProduct(f.size()));
    }
  }
  return points;
}

}  // namespace

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
    auto centre = roomStandpoint(grid, room_id, tour.back(), options.robot_radius);
    if (!centre) return Error{"tour: " + centre.error()};
    if (Status s = driveTo(centre.value()); !s)
      return Error{"tour to room " + std::to_string(room_id) + ": " + s.message()};
    // Look around: the look-outs of the room that are free enough, then back to the centre.
    const Room& room = world.room(room_id);
    if (room.kind == RoomKind::kStairwell || room.kind == RoomKind::kCorridor) continue;
    for (const Eigen::Vector2d& p : lookouts(room.footprint)) {
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

Result<std::vector<Eigen::Vector3d>> planBuildingTour(const World& world, const FreeSpace& space,
                                                      int start_floor, const Eigen::Vector2d& start,
                                                      const std::vector<int>& rooms,
                                                      const PathPlannerOptions& options) {
  const auto gridOf = [&](int floor) -> const FloorGrid* {
    for (const FloorGrid& g : space.floors) {
      if (g.floor == floor) return &g;
    }
    return nullptr;
  };
  std::vector<Eigen::Vector3d> path;
  int floor = start_floor;
  Eigen::Vector2d here = start;
  std::vector<int> leg;  // rooms of the current floor still to visit
  const auto append = [&](const std::vector<Eigen::Vector2d>& points) {
    const double z = world.floors.at(static_cast<size_t>(floor)).z;
    for (size_t i = path.empty() ? 0 : 1; i < points.size(); ++i)
      path.emplace_back(points[i].x(), points[i].y(), z);
  };
  const auto flushLeg = [&](const Eigen::Vector2d* then) -> Status {
    const FloorGrid* grid = gridOf(floor);
    if (grid == nullptr) return Error{"tour: no free space on floor " + std::to_string(floor)};
    auto tour = planRoomTour(world, *grid, here, leg, options);
    if (!tour) return Error{tour.error()};
    std::vector<Eigen::Vector2d> points = tour.value();
    if (then != nullptr) {
      auto tail = planPath(*grid, points.back(), *then, options);
      if (!tail)
        return Error{"tour to the stairs on floor " + std::to_string(floor) + ": " + tail.error()};
      points.insert(points.end(), tail.value().begin() + 1, tail.value().end());
    }
    append(points);
    here = points.back();
    leg.clear();
    return Status::Ok();
  };
  for (const int room_id : rooms) {
    if (room_id < 0 || static_cast<size_t>(room_id) >= world.rooms.size())
      return Error{"tour: no room " + std::to_string(room_id)};
    const int target = world.room(room_id).floor;
    while (floor != target) {
      const bool up = target > floor;
      const Stairs* flight = nullptr;
      for (const Stairs& s : world.stairs) {
        if (world.room(up ? s.lower_room : s.upper_room).floor == floor) flight = &s;
      }
      if (flight == nullptr)
        return Error{"tour: no stairs " + std::string(up ? "up" : "down") + " from floor " +
                     std::to_string(floor)};
      const Eigen::Vector2d from = up ? flight->bottom : flight->top;
      const Eigen::Vector2d to = up ? flight->top : flight->bottom;
      if (Status s = flushLeg(&from); !s) return Error{s.message()};
      floor += up ? 1 : -1;
      const double z = world.floors.at(static_cast<size_t>(floor)).z;
      path.emplace_back(to.x(), to.y(), z);  // the flight: z changes along it
      here = to;
    }
    leg.push_back(room_id);
  }
  if (Status s = flushLeg(nullptr); !s) return Error{s.message()};
  return path;
}

}  // namespace hydra_multi::sim
