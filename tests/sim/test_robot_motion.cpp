#include <gtest/gtest.h>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/exploration.h"
#include "hydra_multi/sim/path_planner.h"
#include "hydra_multi/sim/trajectory.h"

namespace hydra_multi::sim {
namespace {

World building() {
  BuildingOptions options;
  options.rooms_per_side = 4;
  options.seed = 5;
  auto world = generateBuilding(options);
  EXPECT_TRUE(world.ok()) << world.error();
  return std::move(world).value();
}

// A free point of a room: its centre, moved to the nearest free cell with clearance.
Eigen::Vector2d freePointIn(const FloorGrid& g, const Room& room) {
  Eigen::Vector2d best = room.footprint.center();
  double best_clearance = -1.0;
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const size_t i = g.index(x, y);
      if (g.room[i] == room.id && g.clearance[i] > best_clearance) {
        best_clearance = g.clearance[i];
        best = g.cellCenter(x, y);
      }
    }
  }
  return best;
}

// From one room to another across the corridor: every step keeps the robot's clearance and
// the path goes through both rooms' doors.
TEST(PathPlanner, PathsKeepClearanceAndUseDoors) {
  const World world = building();
  const FreeSpace space = computeFreeSpace(world);
  const FloorGrid& g = space.floors[0];
  const Room& from = world.room(1);
  const Room& to = world.room(8);
  auto path = planPath(g, freePointIn(g, from), freePointIn(g, to));
  ASSERT_TRUE(path.ok()) << path.error();
  for (const Eigen::Vector2d& p : path.value()) {
    const Eigen::Vector2i c = g.cellOf(p);
    EXPECT_GE(g.clearance[g.index(c.x(), c.y())], 0.25f);
  }
  for (const Door& door : world.doors) {
    if (door.room_b != from.id && door.room_b != to.id) continue;
    double nearest = 1e9;
    for (const Eigen::Vector2d& p : path.value())
      nearest = std::min(nearest, (p - door.center).norm());
    EXPECT_LT(nearest, 0.2) << "path misses the door of room " << door.room_b;
  }
  for (size_t i = 1; i < path.value().size(); ++i) {
    EXPECT_LE((path.value()[i] - path.value()[i - 1]).norm(), g.resolution * std::sqrt(2.0) + 1e-9);
  }
}

TEST(PathPlanner, BlockedAndUnreachableGoalsAreErrors) {
  const World world = building();
  const FreeSpace space = computeFreeSpace(world);
  const FloorGrid& g = space.floors[0];
  const Eigen::Vector2d in_furniture = world.objects.front().T_world_object.translation().head<2>();
  auto blocked = planPath(g, freePointIn(g, world.room(0)), in_furniture);
  ASSERT_FALSE(blocked.ok());
  EXPECT_NE(blocked.error().find("goal"), std::string::npos) << blocked.error();
  // A room without a door cannot be reached.
  World sealed = world;
  sealed.doors.erase(sealed.doors.begin());
  const FreeSpace sealed_space = computeFreeSpace(sealed);
  auto unreachable =
      planPath(sealed_space.floors[0], freePointIn(sealed_space.floors[0], world.room(0)),
               freePointIn(sealed_space.floors[0], world.room(world.doors.front().room_b)));
  ASSERT_FALSE(unreachable.ok());
  EXPECT_NE(unreachable.error().find("no collision-free path"), std::string::npos);
}

// Keyframes every 0.5 m at 0.5 m/s along a straight 10 m path, facing the way they go.
TEST(Trajectory, KeyframesAlongThePath) {
  const auto keyframes = sampleTrajectory({{0, 0}, {10, 0}}, 2.0, 1'000'000'000);
  ASSERT_EQ(keyframes.size(), 21u);
  for (size_t k = 0; k < keyframes.size(); ++k) {
    EXPECT_EQ(keyframes[k].time_ns, 1'000'000'000 + static_cast<int64_t>(k) * 1'000'000'000);
    EXPECT_TRUE(keyframes[k].T_world_body.translation().isApprox(Eigen::Vector3d(0.5 * k, 0, 3.0)));
    EXPECT_TRUE(keyframes[k].T_world_body.linear().isApprox(Eigen::Matrix3d::Identity()));
  }
}

// Mean final drift (% of the path) over 20 seeds on a straight path of `length` metres.
double meanStraightDrift(double length) {
  const auto truth = sampleTrajectory(std::vector<Eigen::Vector2d>{{0, 0}, {length, 0}}, 0.0, 0);
  double drift_sum = 0.0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    OdometryNoise noise;
    noise.seed = seed;
    const auto odometry = simulateOdometry(truth, noise);
    const Eigen::Isometry3d T_true = truth[0].T_world_body.inverse() * truth.back().T_world_body;
    drift_sum += (odometry.back().translation() - T_true.translation()).norm();
  }
  return 100.0 * drift_sum / 20.0 / length;
}

// Noise-free odometry is the truth seen from the start; noisy odometry drifts by 1.5-3 % of a
// straight 100 m path (mean over 20 seeds), more in proportion on a longer one (the yaw bias),
// and is the same for the same seed.
TEST(Trajectory, OdometryDrift) {
  const std::vector<Eigen::Vector2d> path = {{0, 0}, {300, 0}};
  const auto truth = sampleTrajectory(path, 0.0, 0);
  OdometryNoise none;
  none.translation_sigma = none.yaw_sigma = none.roll_pitch_sigma = 0.0;
  none.scale_bias_sigma = none.yaw_bias_sigma = 0.0;
  const auto exact = simulateOdometry(truth, none);
  for (size_t k = 0; k < truth.size(); k += 50) {
    EXPECT_LT(
        (exact[k].matrix() - (truth[0].T_world_body.inverse() * truth[k].T_world_body).matrix())
            .norm(),
        1e-9);
  }
  OdometryNoise noise;
  const auto once = simulateOdometry(truth, noise), again = simulateOdometry(truth, noise);
  EXPECT_EQ(once.back().matrix(), again.back().matrix());
  const double drift_100 = meanStraightDrift(100.0);
  EXPECT_GT(drift_100, 1.5);
  EXPECT_LT(drift_100, 3.0);
  EXPECT_GT(meanStraightDrift(300.0), drift_100);
}

// A tour enters every room it lists, in order, along one continuous collision-free path.
TEST(Exploration, TourVisitsRoomsInOrder) {
  const World world = building();
  const FreeSpace space = computeFreeSpace(world);
  const FloorGrid& g = space.floors[0];
  const auto start = roomStandpoint(g, 0);
  ASSERT_TRUE(start.ok()) << start.error();
  const std::vector<int> rooms = {2, 7, 4};
  auto tour = planRoomTour(world, g, start.value(), rooms);
  ASSERT_TRUE(tour.ok()) << tour.error();
  size_t next = 0;
  for (size_t i = 0; i < tour.value().size(); ++i) {
    const Eigen::Vector2d& p = tour.value()[i];
    if (i > 0) {
      EXPECT_LE((p - tour.value()[i - 1]).norm(), g.resolution * std::sqrt(2.0) + 1e-9);
    }
    const Eigen::Vector2i c = g.cellOf(p);
    EXPECT_GE(g.clearance[g.index(c.x(), c.y())], 0.25f);
    if (next < rooms.size() && g.room[g.index(c.x(), c.y())] == rooms[next]) ++next;
  }
  EXPECT_EQ(next, rooms.size()) << "the tour skipped a room or changed the order";
  auto bad = planRoomTour(world, g, start.value(), {999});
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "tour: no room 999");
}

}  // namespace
}  // namespace hydra_multi::sim
