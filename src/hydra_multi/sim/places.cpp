#include "hydra_multi/sim/places.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "hydra_multi/core/nearest_neighbors.h"
#include "hydra_multi/sim/visibility.h"

namespace hydra_multi::sim {
namespace {

// Smallest clearance along a segment, or a negative value when it crosses an occupied cell.
double segmentClearance(const FloorGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const int steps =
      std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.5 * grid.resolution))));
  double smallest = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector2i c = grid.cellOf(a + (b - a) * (double(k) / steps));
    if (!grid.inside(c.x(), c.y()) || grid.occupied[grid.index(c.x(), c.y())]) return -1.0;
    smallest = std::min(smallest, double(grid.clearance[grid.index(c.x(), c.y())]));
  }
  return smallest;
}

}  // namespace

PlaceGraph extractPlaces(const FloorGrid& grid, const std::vector<Eigen::Vector2d>& keyframes,
                         const PlacesOptions& options) {
  PlaceGraph graph;
  if (keyframes.empty()) return graph;
  std::vector<Eigen::Vector3d> keyframe_points;
  for (const Eigen::Vector2d& k : keyframes) keyframe_points.emplace_back(k.x(), k.y(), 0.0);
  const NearestNeighbors near_keyframe(keyframe_points);
  // One place per spacing square: the explored GVD cell with the largest clearance in it.
  std::map<std::pair<int, int>, std::pair<double, Eigen::Vector2i>> best;
  for (int y = 0; y < grid.height; ++y) {
    for (int x = 0; x < grid.width; ++x) {
      const size_t i = grid.index(x, y);
      if (!grid.gvd[i]) continue;
      const Eigen::Vector2d p = grid.cellCenter(x, y);
      const auto nearest = near_keyframe.nearest({p.x(), p.y(), 0.0});
      if (nearest.front().distance > options.sensor_range) continue;
      if (!lineOfSight(grid, keyframes[nearest.front().index], p)) continue;
      const std::pair<int, int> square{static_cast<int>(std::floor(p.x() / options.spacing)),
                                       static_cast<int>(std::floor(p.y() / options.spacing))};
      auto it = best.find(square);
      if (it == best.end() || grid.clearance[i] > it->second.first) {
        best[square] = {grid.clearance[i], Eigen::Vector2i(x, y)};
      }
    }
  }
  for (const auto& [square, entry] : best) {
    const Eigen::Vector2i c = entry.second;
    const Eigen::Vector2d p = grid.cellCenter(c.x(), c.y());
    graph.places.push_back({{p.x(), p.y(), grid.z + options.height_above_floor},
                            entry.first,
                            grid.room[grid.index(c.x(), c.y())]});
  }
  for (size_t a = 0; a < graph.places.size(); ++a) {
    for (size_t b = a + 1; b < graph.places.size(); ++b) {
      const Eigen::Vector2d pa = graph.places[a].position.head<2>(),
                            pb = graph.places[b].position.head<2>();
      if ((pa - pb).norm() > options.max_edge_length) continue;
      const double clearance = segmentClearance(grid, pa, pb);
      if (clearance > 0.0) graph.edges.push_back({a, b, clearance});
    }
  }
  return graph;
}

}  // namespace hydra_multi::sim
