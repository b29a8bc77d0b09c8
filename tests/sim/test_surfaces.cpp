#include <gtest/gtest.h>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/surfaces.h"

namespace hydra_multi::sim {
namespace {

World building() {
  BuildingOptions options;
  options.rooms_per_side = 2;
  options.floors = 2;
  return generateBuilding(options).value();
}

// Triangles join nearby vertices; floors, ceilings and walls carry their labels and heights;
// furniture vertices lie on their box.
TEST(Surfaces, LabelledGridsAndBoxes) {
  const World world = building();
  SurfaceOptions options;
  const WorldMesh mesh = generateSurfaces(world, options);
  ASSERT_GT(mesh.vertices.size(), 1000u);
  for (const auto& face : mesh.faces) {
    for (int i = 0; i < 3; ++i) {
      ASSERT_LT(face[i], mesh.vertices.size());
      EXPECT_LT((mesh.vertices[face[i]].position - mesh.vertices[face[(i + 1) % 3]].position).norm(),
                2.0 * options.spacing);
    }
  }
  size_t floors = 0, ceilings = 0, walls = 0, furniture = 0;
  for (const SurfaceVertex& v : mesh.vertices) {
    const Floor& f = world.floors.at(static_cast<size_t>(v.floor));
    if (v.object >= 0) {
      ++furniture;
      const ObjectInstance& o = world.objects.at(static_cast<size_t>(v.object));
      EXPECT_EQ(v.label, o.label);
      const Eigen::Vector3d local = o.T_world_object.inverse() * v.position;
      EXPECT_TRUE(((local.cwiseAbs() - 0.5 * o.size).array() < 1e-9).all());
      EXPECT_NEAR(((local.cwiseAbs() - 0.5 * o.size).cwiseAbs()).minCoeff(), 0.0, 1e-9);
    } else if (v.label == 2) {
      ++floors;
      EXPECT_NEAR(v.position.z(), f.z, 1e-9);
    } else if (v.label == 3) {
      ++ceilings;
      EXPECT_NEAR(v.position.z(), f.z + f.height, 1e-9);
    } else {
      ++walls;
      EXPECT_EQ(v.label, 1u);
      const Rect& r = world.room(v.room).footprint;
      const Eigen::Vector2d p = v.position.head<2>();
      const double to_edge = std::min({std::abs(p.x() - r.min.x()), std::abs(p.x() - r.max.x()),
                                       std::abs(p.y() - r.min.y()), std::abs(p.y() - r.max.y())});
      EXPECT_LT(to_edge, 1e-9);
    }
  }
  EXPECT_GT(floors, 100u);
  EXPECT_EQ(floors, ceilings);
  EXPECT_GT(walls, 100u);
  EXPECT_GT(furniture, 100u);
}

// Doors are openings: no wall vertex below the door height within a door's width.
TEST(Surfaces, DoorsAreOpen) {
  const World world = building();
  SurfaceOptions options;
  const WorldMesh mesh = generateSurfaces(world, options);
  for (const SurfaceVertex& v : mesh.vertices) {
    if (v.label != 1 || v.object >= 0) continue;
    const double z = v.position.z() - world.floors.at(static_cast<size_t>(v.floor)).z;
    for (const Door& door : world.doors) {
      if (door.floor != v.floor || z > options.door_height - 1e-9) continue;
      const bool in_opening = std::abs(v.position.x() - door.center.x()) < 0.5 * door.width - 1e-9 &&
                              std::abs(v.position.y() - door.center.y()) < 0.5;
      EXPECT_FALSE(in_opening);
    }
  }
}

}  // namespace
}  // namespace hydra_multi::sim
