#include <gtest/gtest.h>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/visibility.h"

namespace hydra_multi::sim {
namespace {

// Two rooms below a corridor (room 1 at x in [0, 4], room 2 at x in [4.15, 8.15], y in [-5.15,
// -0.15]; doors centred at x = 2 and x = 6.15) and hand-placed objects.
struct Scene {
  World world;
  FreeSpace space;
};

Scene scene(const std::vector<std::pair<int, Eigen::Vector2d>>& objects) {
  BuildingOptions options;
  options.rooms_per_side = 2;
  Scene s{generateBuilding(options).value(), {}};
  s.world.objects.clear();
  for (const auto& [room, xy] : objects) {
    ObjectInstance o;
    o.id = static_cast<int>(s.world.objects.size());
    o.room = room;
    o.label = 5;
    o.size = Eigen::Vector3d(0.2, 0.2, 0.5);
    o.T_world_object.translation() << xy.x(), xy.y(), 0.25;
    s.world.objects.push_back(o);
  }
  s.space = computeFreeSpace(s.world);
  return s;
}

Eigen::Isometry3d bodyAt(const Eigen::Vector2d& xy, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << xy.x(), xy.y(), 1.0;
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

// In room 1 looking east: the object ahead is seen, the one behind is not (field of view), the one
// in room 2 beyond the wall is not (line of sight).
TEST(Visibility, FieldOfViewAndWalls) {
  const Scene s = scene({{1, {3.0, -2.5}}, {1, {0.5, -2.5}}, {2, {5.5, -2.5}}});
  EXPECT_EQ(visibleObjects(s.world, s.space, 0, bodyAt({1.5, -2.5}, 0.0)), std::vector<int>{0});
  // Turned around, only the one behind is seen.
  EXPECT_EQ(visibleObjects(s.world, s.space, 0, bodyAt({1.5, -2.5}, M_PI)), std::vector<int>{1});
}

// From the corridor looking into room 1 through its door: straight through is seen, past the door
// frame is hidden, and beyond the range nothing is seen.
TEST(Visibility, ThroughDoors) {
  const Scene s = scene({{1, {2.0, -2.0}}, {1, {0.5, -2.0}}, {1, {2.0, -4.9}}});
  SensorModel sensor;
  sensor.range = 6.0;
  const Eigen::Isometry3d facing_room = bodyAt({2.0, 1.0}, -0.5 * M_PI);
  const std::vector<int> expected = {0, 2};
  EXPECT_EQ(visibleObjects(s.world, s.space, 0, facing_room, sensor), expected);
  sensor.range = 5.0;  // object 2 is 5.9 m away
  EXPECT_EQ(visibleObjects(s.world, s.space, 0, facing_room, sensor), std::vector<int>{0});
  EXPECT_TRUE(lineOfSight(s.space.floors[0], {2.0, 1.0}, {2.0, -2.0}));
  EXPECT_FALSE(lineOfSight(s.space.floors[0], {2.0, 1.0}, {0.5, -2.0}));
}

}  // namespace
}  // namespace hydra_multi::sim
