#pragma once
// The world's surfaces as a labelled triangle mesh (ground truth): floors, ceilings and walls of
// every room (walls with their door openings left out) and the top and sides of every piece of
// furniture, each a grid of vertices about `spacing` apart, two triangles per grid cell. A robot
// maps the part of it that its sensor sees (robot_mapper.h).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "hydra_multi/sim/world.h"

namespace hydra_multi::sim {

struct SurfaceOptions {
  double spacing = 0.3;      ///< vertex spacing (m)
  double door_height = 2.0;  ///< openings are cut up to this height (m)
};

struct SurfaceVertex {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  uint32_t label = 0;  ///< semantic class (wall, floor, ceiling or the object's)
  int floor = 0;
  int room = -1;
  int object = -1;  ///< the object it belongs to; -1 for structure
};

struct WorldMesh {
  std::vector<SurfaceVertex> vertices;
  std::vector<std::array<uint32_t, 3>> faces;
};

WorldMesh generateSurfaces(const World& world, const SurfaceOptions& options = {});

}  // namespace hydra_multi::sim
