#pragma once
// Exploration tours: a robot drives from its start to each of a list of rooms in turn and looks
// around inside each (a loop through look-out points about 4 m apart, the four quarter points of
// an ordinary room), along collision-free paths (path_planner.h); rooms on another floor are
// reached by the stairs (World::stairs). Which robot visits which rooms is the preset's choice.

#include <optional>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/sim/path_planner.h"

namespace hydra_multi::sim {

/// The free cell of `room` with the most clearance (a good place to stand in it). With
/// `reachable_from`, only cells a robot of `robot_radius` can drive to from there count
/// (furniture may wall off part of a room).
Result<Eigen::Vector2d> roomStandpoint(const FloorGrid& grid, int room,
                                       const std::optional<Eigen::Vector2d>& reachable_from = {},
                                       double robot_radius = 0.25);

/// The path of a tour on one floor: start, then every room of `rooms` in order.
Result<std::vector<Eigen::Vector2d>> planRoomTour(const World& world, const FloorGrid& grid,
                                                  const Eigen::Vector2d& start,
                                                  const std::vector<int>& rooms,
                                                  const PathPlannerOptions& options = {});

/// A tour through rooms on any floor, as a 3D polyline: x-y on the floors and z the floor's
/// height; on stairs z rises or falls along the flight. Fails when a room is unreachable or a
/// floor change has no stairs.
Result<std::vector<Eigen::Vector3d>> planBuildingTour(const World& world, const FreeSpace& space,
                                                      int start_floor, const Eigen::Vector2d& start,
                                                      const std::vector<int>& rooms,
                                                      const PathPlannerOptions& options = {});

}  // namespace hydra_multi::sim
