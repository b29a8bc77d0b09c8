#include <gtest/gtest.h>

#include <algorithm>
#include <deque>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/free_space.h"

namespace hydra_multi::sim {
namespace {

World singleRoom(double w, double d) {
  World world;
  world.floors.push_back({0, 0.0, 3.0});
  Room room;
  room.id = 0;
  room.kind = RoomKind::kOffice;
  room.footprint = {{0.0, 0.0}, {w, d}};
  world.rooms.push_back(room);
  return world;
}

// A 4 x 6 m empty room: clearance 2 m at the centre; the GVD is its medial axis, every GVD cell
// about equally far from its two nearest walls, and the centre line x = 2 between y = 2 and 4 on
// it.
TEST(FreeSpace, MedialAxisOfARoom) {
  const FreeSpace space = computeFreeSpace(singleRoom(4.0, 6.0));
  ASSERT_EQ(space.floors.size(), 1u);
  const FloorGrid& g = space.floors[0];
  const Eigen::Vector2i centre = g.cellOf({2.0, 3.0});
  EXPECT_NEAR(g.clearance[g.index(centre.x(), centre.y())], 2.0, 0.1);
  size_t gvd_cells = 0;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      if (!g.gvd[g.index(x, y)]) continue;
      ++gvd_cells;
      const Eigen::Vector2d p = g.cellCenter(x, y);
      std::vector<double> walls = {p.x(), 4.0 - p.x(), p.y(), 6.0 - p.y()};
      std::sort(walls.begin(), walls.end());
      EXPECT_NEAR(walls[0], walls[1], 0.25) << p.transpose();
      EXPECT_GE(g.clearance[g.index(x, y)], 0.3f);
    }
  }
  EXPECT_GT(gvd_cells, 20u);
  for (double y = 2.05; y < 4.0; y += 0.1) {
    const Eigen::Vector2i c = g.cellOf({1.95, y});
    const Eigen::Vector2i c2 = g.cellOf({2.05, y});
    EXPECT_TRUE(g.gvd[g.index(c.x(), c.y())] || g.gvd[g.index(c2.x(), c2.y())]) << y;
  }
  for (const Eigen::Vector3d& p : space.gvdPoints(1.2)) EXPECT_DOUBLE_EQ(p.z(), 1.2);
}

// In a generated building every room is reachable from the corridor through its door, furniture
// is an obstacle, and the room voxels are the room's free cells.
TEST(FreeSpace, DoorsConnectRoomsAndFurnitureBlocks) {
  for (const uint64_t seed : {1, 5, 9}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    BuildingOptions options;
    options.seed = seed;
    options.rooms_per_side = 4;
    auto world = generateBuilding(options);
    ASSERT_TRUE(world.ok()) << world.error();
    const FreeSpace space = computeFreeSpace(world.value());
    const FloorGrid& g = space.floors[0];
    // Flood fill from the corridor's centre over free cells.
    std::vector<uint8_t> reached(g.occupied.size(), 0);
    const Eigen::Vector2i start = g.cellOf(world.value().room(0).footprint.center());
    std::deque<Eigen::Vector2i> queue = {start};
    reached[g.index(start.x(), start.y())] = 1;
    while (!queue.empty()) {
      const Eigen::Vector2i c = queue.front();
      queue.pop_front();
      for (const Eigen::Vector2i& step : {Eigen::Vector2i(1, 0), Eigen::Vector2i(-1, 0),
                                          Eigen::Vector2i(0, 1), Eigen::Vector2i(0, -1)}) {
        const Eigen::Vector2i n = c + step;
        if (!g.inside(n.x(), n.y())) continue;
        const size_t i = g.index(n.x(), n.y());
        if (g.occupied[i] || reached[i]) continue;
        reached[i] = 1;
        queue.push_back(n);
      }
    }
    const auto voxels = space.roomVoxels(world.value().rooms.size());
    for (const Room& room : world.value().rooms) {
      const auto& cells = voxels[static_cast<size_t>(room.id)];
      ASSERT_FALSE(cells.empty());
      size_t reachable = 0;
      for (const Eigen::Vector3i& v : cells) reachable += reached[g.index(v.x(), v.y())];
      EXPECT_GT(reachable, cells.size() / 2) << "room " << room.id << " is cut off";
      const double area_cells = room.footprint.size().prod() / (g.resolution * g.resolution);
      // At most the cells whose centres fall in the footprint, edges included.
      const Eigen::Vector2d cells_per_side = room.footprint.size() / g.resolution;
      EXPECT_LE(static_cast<double>(cells.size()),
                (cells_per_side.x() + 1) * (cells_per_side.y() + 1));
      EXPECT_GE(static_cast<double>(cells.size()), area_cells * 0.4);
    }
    for (const ObjectInstance& object : world.value().objects) {
      const Eigen::Vector2i c = g.cellOf(object.T_world_object.translation().head<2>());
      EXPECT_TRUE(g.occupied[g.index(c.x(), c.y())]) << "object " << object.id;
      EXPECT_EQ(g.room[g.index(c.x(), c.y())], -1);
    }
  }
}

}  // namespace
}  // namespace hydra_multi::sim
