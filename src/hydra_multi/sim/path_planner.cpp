#include "hydra_multi/sim/path_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <string>

namespace hydra_multi::sim {

Result<std::vector<Eigen::Vector2d>> planPath(const FloorGrid& grid, const Eigen::Vector2d& start,
                                              const Eigen::Vector2d& goal,
                                              const PathPlannerOptions& options) {
  const auto passable = [&](int x, int y) {
    if (!grid.inside(x, y)) return false;
    const size_t i = grid.index(x, y);
    return !grid.occupied[i] && grid.clearance[i] >= options.robot_radius;
  };
  const Eigen::Vector2i s = grid.cellOf(start), g = grid.cellOf(goal);
  const auto where = [](const Eigen::Vector2d& p) {
    return "(" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ")";
  };
  if (!passable(s.x(), s.y())) return Error{"path: start " + where(start) + " is not free space"};
  if (!passable(g.x(), g.y())) return Error{"path: goal " + where(goal) + " is not free space"};

  const size_t n = static_cast<size_t>(grid.width) * static_cast<size_t>(grid.height);
  std::vector<double> cost(n, std::numeric_limits<double>::infinity());
  std::vector<int> previous(n, -1);
  using Entry = std::pair<double, int>;  // (cost + heuristic, cell)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  const int start_index = static_cast<int>(grid.index(s.x(), s.y()));
  const int goal_index = static_cast<int>(grid.index(g.x(), g.y()));
  const auto heuristic = [&](int cell) {
    return grid.resolution * std::hypot(cell % grid.width - g.x(), cell / grid.width - g.y());
  };
  cost[static_cast<size_t>(start_index)] = 0.0;
  open.emplace(heuristic(start_index), start_index);
  while (!open.empty()) {
    const auto [priority, cell] = open.top();
    open.pop();
    if (cell == goal_index) break;
    if (priority > cost[static_cast<size_t>(cell)] + heuristic(cell) + 1e-12) continue;  // stale
    const int cx = cell % grid.width, cy = cell / grid.width;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || !passable(cx + dx, cy + dy)) continue;
        const int next = static_cast<int>(grid.index(cx + dx, cy + dy));
        const double clearance = grid.clearance[static_cast<size_t>(next)];
        const double penalty =
            clearance >= options.preferred_clearance
                ? 1.0
                : 1.0 + options.clearance_penalty * (1.0 - clearance / options.preferred_clearance);
        const double step = grid.resolution * std::hypot(dx, dy) * penalty;
        const double candidate = cost[static_cast<size_t>(cell)] + step;
        if (candidate < cost[static_cast<size_t>(next)]) {
          cost[static_cast<size_t>(next)] = candidate;
          previous[static_cast<size_t>(next)] = cell;
          open.emplace(candidate + heuristic(next), next);
        }
      }
    }
  }
  if (!std::isfinite(cost[static_cast<size_t>(goal_index)])) {
    return Error{"path: no collision-free path from " + where(start) + " to " + where(goal)};
  }
  std::vector<Eigen::Vector2d> path;
  for (int cell = goal_index; cell >= 0; cell = previous[static_cast<size_t>(cell)]) {
    path.push_back(grid.cellCenter(cell % grid.width, cell / grid.width));
  }
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace hydra_multi::sim
