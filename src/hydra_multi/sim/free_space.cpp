#include "hydra_multi/sim/free_space.h"

#include <cmath>
#include <deque>
#include <limits>

namespace hydra_multi::sim {
namespace {

// Marks the cells whose centres lie inside the rectangle.
template <typename Mark>
void forCells(const FloorGrid& grid, const Rect& rect, Mark mark) {
  const Eigen::Vector2i lo = grid.cellOf(rect.min), hi = grid.cellOf(rect.max);
  for (int y = std::max(lo.y(), 0); y <= std::min(hi.y(), grid.height - 1); ++y) {
    for (int x = std::max(lo.x(), 0); x <= std::min(hi.x(), grid.width - 1); ++x) {
      if (rect.contains(grid.cellCenter(x, y))) mark(x, y);
    }
  }
}

}  // namespace

Eigen::Vector2i FloorGrid::cellOf(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d c = (p - origin) / resolution;
  return {static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))};
}

std::vector<Eigen::Vector3d> FreeSpace::gvdPoints(double height_above_floor) const {
  std::vector<Eigen::Vector3d> points;
  for (const FloorGrid& g : floors) {
    for (int y = 0; y < g.height; ++y) {
      for (int x = 0; x < g.width; ++x) {
        if (!g.gvd[g.index(x, y)]) continue;
        const Eigen::Vector2d c = g.cellCenter(x, y);
        points.emplace_back(c.x(), c.y(), g.z + height_above_floor);
      }
    }
  }
  return points;
}

std::vector<std::vector<Eigen::Vector3i>> FreeSpace::roomVoxels(size_t num_rooms) const {
  std::vector<std::vector<Eigen::Vector3i>> rooms(num_rooms);
  for (const FloorGrid& g : floors) {
    for (int y = 0; y < g.height; ++y) {
      for (int x = 0; x < g.width; ++x) {
        const int r = g.room[g.index(x, y)];
        if (r >= 0 && static_cast<size_t>(r) < num_rooms)
          rooms[static_cast<size_t>(r)].emplace_back(x, y, g.floor);
      }
    }
  }
  return rooms;
}

FreeSpace computeFreeSpace(const World& world, const FreeSpaceOptions& options) {
  FreeSpace space;
  for (const Floor& floor : world.floors) {
    // The grid covers the floor's rooms with a one-metre border of outside.
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Room& room : world.rooms) {
      if (room.floor != floor.index) continue;
      lo = lo.cwiseMin(room.footprint.min);
      hi = hi.cwiseMax(room.footprint.max);
    }
    FloorGrid g;
    g.floor = floor.index;
    g.z = floor.z;
    g.resolution = options.resolution;
    g.origin = lo - Eigen::Vector2d::Constant(1.0);
    g.width = static_cast<int>(std::ceil((hi.x() - lo.x() + 2.0) / g.resolution));
    g.height = static_cast<int>(std::ceil((hi.y() - lo.y() + 2.0) / g.resolution));
    const size_t n = static_cast<size_t>(g.width) * static_cast<size_t>(g.height);
    g.occupied.assign(n, 1);
    g.room.assign(n, -1);
    for (const Room& room : world.rooms) {
      if (room.floor != floor.index) continue;
      forCells(g, room.footprint, [&](int x, int y) {
        g.occupied[g.index(x, y)] = 0;
        g.room[g.index(x, y)] = room.id;
      });
    }
    for (const Door& door : world.doors) {
      if (door.floor != floor.index) continue;
      // The opening crosses the wall between the two rooms' footprints.
      const Room& a = world.room(door.room_a);
      const Room& b = world.room(door.room_b);
      const double gap_lo = std::min(std::max(a.footprint.min.y(), b.footprint.min.y()),
                                     std::min(a.footprint.max.y(), b.footprint.max.y()));
      const double gap_hi = std::max(std::max(a.footprint.min.y(), b.footprint.min.y()),
                                     std::min(a.footprint.max.y(), b.footprint.max.y()));
      const Rect opening{{door.center.x() - 0.5 * door.width, gap_lo - 1e-6},
                         {door.center.x() + 0.5 * door.width, gap_hi + 1e-6}};
      forCells(g, opening, [&](int x, int y) { g.occupied[g.index(x, y)] = 0; });
    }
    g.wall = g.occupied;  // before the furniture goes in
    for (const ObjectInstance& object : world.objects) {
      if (world.room(object.room).floor != floor.index) continue;
      Eigen::Vector2d olo = Eigen::Vector2d::Constant(1e300), ohi = -olo;
      for (const double sx : {-0.5, 0.5}) {
        for (const double sy : {-0.5, 0.5}) {
          const Eigen::Vector3d corner =
              object.T_world_object *
              Eigen::Vector3d(sx * object.size.x(), sy * object.size.y(), 0);
          olo = olo.cwiseMin(corner.head<2>());
          ohi = ohi.cwiseMax(corner.head<2>());
        }
      }
      forCells(g, Rect{olo, ohi}, [&](int x, int y) {
        g.occupied[g.index(x, y)] = 1;
        g.room[g.index(x, y)] = -1;
      });
    }

    // Brushfire: every cell learns its nearest obstacle cell (8-connected propagation of sites).
    std::vector<int> site(n, -1);
    std::deque<int> queue;
    for (size_t i = 0; i < n; ++i) {
      if (g.occupied[i]) {
        site[i] = static_cast<int>(i);
        queue.push_back(static_cast<int>(i));
      }
    }
    const auto dist2 = [&](int a, int b) {
      const int ax = a % g.width, ay = a / g.width, bx = b % g.width, by = b / g.width;
      return double(ax - bx) * (ax - bx) + double(ay - by) * (ay - by);
    };
    while (!queue.empty()) {
      const int c = queue.front();
      queue.pop_front();
      const int cx = c % g.width, cy = c / g.width;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || !g.inside(cx + dx, cy + dy)) continue;
          const int nb = static_cast<int>(g.index(cx + dx, cy + dy));
          if (site[nb] < 0 || dist2(nb, site[c]) < dist2(nb, site[nb])) {
            site[nb] = site[c];
            queue.push_back(nb);
          }
        }
      }
    }
    g.clearance.assign(n, 0.0f);
    g.gvd.assign(n, 0);
    const double separation2 = std::pow(options.gvd_site_separation / g.resolution, 2);
    for (int y = 0; y < g.height; ++y) {
      for (int x = 0; x < g.width; ++x) {
        const size_t i = g.index(x, y);
        if (g.occupied[i]) continue;
        const double clearance = std::sqrt(dist2(static_cast<int>(i), site[i])) * g.resolution;
        g.clearance[i] = static_cast<float>(clearance);
        if (clearance < options.gvd_min_clearance) continue;
        for (int dy = -1; dy <= 1 && !g.gvd[i]; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            if (!g.inside(x + dx, y + dy)) continue;
            const size_t nb = g.index(x + dx, y + dy);
            if (!g.occupied[nb] && dist2(site[i], site[nb]) > separation2) {
              g.gvd[i] = 1;
              break;
            }
          }
        }
      }
    }
    space.floors.push_back(std::move(g));
  }
  return space;
}

}  // namespace hydra_multi::sim
