#pragma once
// Free-space ground truth of a world, per floor on a 2D grid (cells of `resolution` metres at a
// robot's height): obstacles are walls (everything outside the rooms, but for door openings) and
// furniture footprints; a brushfire from all obstacles gives every free cell its nearest obstacle
// cell, hence its clearance; the generalized Voronoi diagram (GVD) is the free cells whose nearest
// obstacle differs from a neighbour's by more than `gvd_site_separation`: points with two nearest
// obstacles, the medial axis that places live on. Rooms' free cells give the room voxels that the
// rooms metric compares (eval/scene_metrics.h).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "hydra_multi/sim/world.h"

namespace hydra_multi::sim {

struct FreeSpaceOptions {
  double resolution = 0.1;           ///< cell side (m)
  double gvd_site_separation = 0.5;  ///< nearest obstacles this far apart make a GVD cell (m)
  double gvd_min_clearance = 0.3;    ///< GVD cells closer to an obstacle are dropped (m)
};

struct FloorGrid {
  int floor = 0;
  double z = 0.0;
  double resolution = 0.1;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< corner of cell (0, 0)
  int width = 0, height = 0;                         ///< cells along x and y
  std::vector<uint8_t> occupied;                     ///< 1: wall, outside or furniture
  std::vector<uint8_t> wall;                         ///< 1: wall or outside (not furniture)
  std::vector<float> clearance;                      ///< distance to the nearest obstacle (m)
  std::vector<int> room;                             ///< room id of a free cell; -1 otherwise
  std::vector<uint8_t> gvd;                          ///< 1: on the GVD

  size_t index(int x, int y) const { return static_cast<size_t>(y) * width + x; }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  Eigen::Vector2d cellCenter(int x, int y) const {
    return origin + resolution * Eigen::Vector2d(x + 0.5, y + 0.5);
  }
  /// The cell that holds p (may be outside the grid).
  Eigen::Vector2i cellOf(const Eigen::Vector2d& p) const;
};

struct FreeSpace {
  std::vector<FloorGrid> floors;

  /// Centres of all GVD cells, at each floor's z plus `height_above_floor`.
  std::vector<Eigen::Vector3d> gvdPoints(double height_above_floor = 1.0) const;
  /// Free cells of every room (not the doorways), as voxel keys (x, y, floor).
  std::vector<std::vector<Eigen::Vector3i>> roomVoxels(size_t num_rooms) const;
};

FreeSpace computeFreeSpace(const World& world, const FreeSpaceOptions& options = {});

}  // namespace hydra_multi::sim
