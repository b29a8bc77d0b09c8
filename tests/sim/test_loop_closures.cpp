#include <gtest/gtest.h>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/exploration.h"
#include "hydra_multi/sim/free_space.h"
#include "hydra_multi/sim/loop_closures.h"

namespace hydra_multi::sim {
namespace {

struct Scene {
  World world;
  FreeSpace space;
  std::vector<StampedPose> truth;
  std::vector<int> rooms;
};

// A robot that starts in the corridor and tours rooms 1, 2, then 1 again, in a building with or without identical rooms.
Scene tour(bool identical) {
  BuildingOptions options;
  options.rooms_per_side = 3;
  options.identical_rooms = identical;
  options.room_kind = RoomKind::kStudentRoom;
  Scene s;
  s.world = generateBuilding(options).value();
  s.space = computeFreeSpace(s.world);
  const FloorGrid& grid = s.space.floors[0];
  const auto path =
      planRoomTour(s.world, grid, roomStandpoint(grid, 0).value(), {1, 2, 1}).value();
  s.truth = sampleTrajectory(path, 0.0, 0);
  for (const StampedPose& p : s.truth) {
    const Eigen::Vector2i c = grid.cellOf(p.T_world_body.translation().head<2>());
    s.rooms.push_back(grid.room[grid.index(c.x(), c.y())]);
  }
  return s;
}

// Revisits in a building of distinct rooms: closures between keyframes close in space and far
// apart in time, measuring the true relative pose up to noise.
TEST(LoopClosures, RevisitsMeasureTheTruth) {
  const Scene s = tour(false);
  LoopClosureOptions options;
  options.min_time_gap_s = 10.0;
  options.gross_error_share = 0.0;
  const auto closures = simulateLoopClosures(s.world, s.truth, s.rooms, options);
  ASSERT_GE(closures.size(), 2u);
  for (const SimulatedLoopClosure& c : closures) {
    EXPECT_TRUE(c.correct);
    EXPECT_EQ(c.kind, SimulatedLoopClosure::Kind::kRevisit);
    EXPECT_LT(c.from, c.to);
    EXPECT_GE(s.truth[c.to].time_ns - s.truth[c.from].time_ns, 10'000'000'000);
    const Eigen::Isometry3d truth =
        s.truth[c.from].T_world_body.inverse() * s.truth[c.to].T_world_body;
    EXPECT_LT((c.T_from_to.translation() - truth.translation()).norm(), 0.2);
  }
  EXPECT_EQ(closures.size(), simulateLoopClosures(s.world, s.truth, s.rooms, options).size());
}

// Identical rooms fool the robot: a closure between the two look-alike rooms measures the pose
// in the room frames (what registering the two views gives) and is labelled wrong; gross errors
// are labelled wrong too.
TEST(LoopClosures, AliasingAndGrossErrorsAreWrong) {
  const Scene s = tour(true);
  LoopClosureOptions options;
  options.min_time_gap_s = 10.0;
  options.aliasing_acceptance = 1.0;
  options.gross_error_share = 0.0;
  const auto closures = simulateLoopClosures(s.world, s.truth, s.rooms, options);
  size_t aliased = 0;
  for (const SimulatedLoopClosure& c : closures) {
    if (c.kind != SimulatedLoopClosure::Kind::kAliasing) continue;
    ++aliased;
    EXPECT_FALSE(c.correct);
    EXPECT_NE(s.rooms[c.from], s.rooms[c.to]);
    const Eigen::Isometry3d truth =
        s.truth[c.from].T_world_body.inverse() * s.truth[c.to].T_world_body;
    EXPECT_GT((c.T_from_to.translation() - truth.translation()).norm(), 1.0);
  }
  EXPECT_GE(aliased, 1u);

  options.aliasing_acceptance = 0.0;
  options.gross_error_share = 1.0;
  for (const SimulatedLoopClosure& c : simulateLoopClosures(s.world, s.truth, s.rooms, options)) {
    EXPECT_EQ(c.kind, SimulatedLoopClosure::Kind::kGrossError);
    EXPECT_FALSE(c.correct);
  }
}

}  // namespace
}  // namespace hydra_multi::sim
