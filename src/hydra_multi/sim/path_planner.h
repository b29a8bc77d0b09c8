#pragma once
// Collision-free paths on a floor's free-space grid: A* over 8-connected free cells whose clearance
// is at least the robot's radius, with a cost that prefers staying away from obstacles (paths run
// along corridors' middles and through doors' centres, as a careful robot drives).

#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/sim/free_space.h"

namespace hydra_multi::sim {

struct PathPlannerOptions {
  double robot_radius = 0.25;        ///< cells closer to an obstacle are not entered (m)
  double preferred_clearance = 0.6;  ///< below this, steps cost more (m)
  double clearance_penalty = 4.0;    ///< extra cost factor at zero clearance
};

/// The path from start to goal as cell centres (start and goal cells included); an error names
/// which end is blocked or says that no path exists.
Result<std::vector<Eigen::Vector2d>> planPath(const FloorGrid& grid, const Eigen::Vector2d& start,
                                              const Eigen::Vector2d& goal,
                                              const PathPlannerOptions& options = {});

}  // namespace hydra_multi::sim
