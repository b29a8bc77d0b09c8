// Each preset's basic properties (issue 4): building, team, start poses, tours. Planning only
// (no mapping), so every preset at its real size stays fast.

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "hydra_multi/sim/dataset.h"

namespace hydra_multi::sim {
namespace {

SimulatedDataset plan(const std::string& preset, uint64_t seed = 1,
                      std::optional<int> robots = std::nullopt, double scale = 1.0) {
  auto config = presetConfig(preset, seed, robots, scale);
  EXPECT_TRUE(config.ok()) << config.error();
  auto dataset = planDataset(config.value());
  EXPECT_TRUE(dataset.ok()) << dataset.error();
  return std::move(dataset).value();
}

double pathLength(const RobotRun& run) {
  double length = 0.0;
  for (size_t k = 1; k < run.truth.size(); ++k) {
    length += (run.truth[k].T_world_body.translation() -
               run.truth[k - 1].T_world_body.translation())
                  .norm();
  }
  return length;
}

double totalPath(const SimulatedDataset& d) {
  double total = 0.0;
  for (const RobotRun& run : d.runs) total += pathLength(run);
  return total;
}

// The rooms a robot's keyframes are in.
std::set<int> roomsVisited(const SimulatedDataset& d, const RobotRun& run) {
  std::set<int> rooms;
  for (size_t k = 0; k < run.truth.size(); ++k) {
    const int room = d.sensed->roomOf(run.floors[k], run.truth[k].T_world_body.translation());
    if (room >= 0 && d.sensed->world.room(room).kind != RoomKind::kCorridor) rooms.insert(room);
  }
  return rooms;
}

size_t shared(const std::set<int>& a, const std::set<int>& b) {
  size_t n = 0;
  for (const int x : a) n += b.count(x);
  return n;
}

TEST(Presets, NamesAndErrors) {
  for (const std::string& name : presetNames()) {
    auto config = presetConfig(name, 3);
    ASSERT_TRUE(config.ok()) << name;
    EXPECT_EQ(config.value().sensors.size(), static_cast<size_t>(config.value().robots));
  }
  const auto unknown = presetConfig("castle", 1);
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().find("unknown preset 'castle'"), std::string::npos);
  EXPECT_NE(unknown.error().find("office-3"), std::string::npos);
  EXPECT_FALSE(presetConfig("tiny", 1, 0).ok());
  EXPECT_TRUE(presetConfig("office-3", 1, 20).ok());
  EXPECT_FALSE(presetConfig("tiny", 1, 21).ok());
  EXPECT_FALSE(presetConfig("tiny", 1, std::nullopt, 10.0).ok());
}

// office-3: one floor of about 40 x 30 m with offices, open spaces and a kitchen; 3 robots on
// different but overlapping parts, each starting at its own place.
TEST(Presets, Office3) {
  const SimulatedDataset d = plan("office-3");
  const World& world = d.sensed->world;
  EXPECT_EQ(world.floors.size(), 1u);
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  std::set<RoomKind> kinds;
  for (const Room& room : world.rooms) {
    lo = lo.cwiseMin(room.footprint.min);
    hi = hi.cwiseMax(room.footprint.max);
    kinds.insert(room.kind);
  }
  EXPECT_NEAR(hi.x() - lo.x(), 40.0, 3.0);
  EXPECT_NEAR(hi.y() - lo.y(), 28.0, 3.0);
  EXPECT_TRUE(kinds.count(RoomKind::kOffice) && kinds.count(RoomKind::kOpenSpace) &&
              kinds.count(RoomKind::kKitchen) && kinds.count(RoomKind::kCorridor));
  ASSERT_EQ(d.runs.size(), 3u);
  for (size_t a = 0; a < 3; ++a) {
    EXPECT_GT(pathLength(d.runs[a]), 150.0);
    EXPECT_EQ(d.runs[a].sensor.kind, "rgbd");
    for (size_t b = a + 1; b < 3; ++b) {
      EXPECT_GT((d.runs[a].truth.front().T_world_body.translation() -
                 d.runs[b].truth.front().T_world_body.translation())
                    .norm(),
                3.0);
    }
  }
  // Neighbours in the team overlap; none covers everything alone.
  const auto r0 = roomsVisited(d, d.runs[0]), r1 = roomsVisited(d, d.runs[1]),
             r2 = roomsVisited(d, d.runs[2]);
  EXPECT_GE(shared(r0, r1), 1u);
  EXPECT_GE(shared(r1, r2), 1u);
  EXPECT_LT(r0.size(), world.rooms.size() - 1);
}

// residence-3f: three floors joined by stairs; 2 robots starting on different floors, both
// exploring the middle one; about 400 m in total.
TEST(Presets, Residence3f) {
  const SimulatedDataset d = plan("residence-3f");
  const World& world = d.sensed->world;
  EXPECT_EQ(world.floors.size(), 3u);
  EXPECT_EQ(world.stairs.size(), 2u);
  ASSERT_EQ(d.runs.size(), 2u);
  EXPECT_EQ(d.runs[0].floors.front(), 0);
  EXPECT_EQ(d.runs[1].floors.front(), 2);
  for (const RobotRun& run : d.runs) {
    EXPECT_TRUE(std::count(run.floors.begin(), run.floors.end(), 1) > 20);
    // One continuous path, stairs included.
    for (size_t k = 1; k < run.truth.size(); ++k) {
      ASSERT_LT((run.truth[k].T_world_body.translation() -
                 run.truth[k - 1].T_world_body.translation())
                    .norm(),
                0.51);
    }
  }
  EXPECT_GE(shared(roomsVisited(d, d.runs[0]), roomsVisited(d, d.runs[1])), 1u);
  EXPECT_GT(totalPath(d), 330.0);
  EXPECT_LT(totalPath(d), 500.0);
}

// dorm-2: one long floor of identical student rooms, 2 robots starting in different rooms,
// about 500 m in total; dorm-2-meet: starting at opposite ends and meeting in the middle.
TEST(Presets, Dorms) {
  const SimulatedDataset d = plan("dorm-2");
  const World& world = d.sensed->world;
  std::set<int> layouts;
  for (const Room& room : world.rooms) {
    if (room.kind == RoomKind::kStudentRoom) layouts.insert(room.layout);
  }
  EXPECT_EQ(layouts.size(), 1u);  // every student room alike
  EXPECT_GE(*layouts.begin(), 0);
  ASSERT_EQ(d.runs.size(), 2u);
  const int start0 = d.sensed->roomOf(0, d.runs[0].truth.front().T_world_body.translation());
  const int start1 = d.sensed->roomOf(0, d.runs[1].truth.front().T_world_body.translation());
  EXPECT_NE(start0, start1);
  EXPECT_GT(totalPath(d), 400.0);
  EXPECT_LT(totalPath(d), 600.0);

  const SimulatedDataset meet = plan("dorm-2-meet");
  double lo = 1e9, hi = -1e9;
  for (const Room& room : meet.sensed->world.rooms) {
    lo = std::min(lo, room.footprint.min.x());
    hi = std::max(hi, room.footprint.max.x());
  }
  const double x0 = meet.runs[0].truth.front().T_world_body.translation().x();
  const double x1 = meet.runs[1].truth.front().T_world_body.translation().x();
  EXPECT_LT(x0, lo + 0.15 * (hi - lo));
  EXPECT_GT(x1, hi - 0.15 * (hi - lo));
  EXPECT_GE(shared(roomsVisited(meet, meet.runs[0]), roomsVisited(meet, meet.runs[1])), 2u);
}

// hetero-2: dorm-2-meet with robot 1 a lidar robot: no labels, no objects.
TEST(Presets, Hetero2) {
  auto config = presetConfig("hetero-2", 1);
  ASSERT_TRUE(config.ok());
  ASSERT_EQ(config.value().sensors.size(), 2u);
  EXPECT_EQ(config.value().sensors[0].kind, "rgbd");
  EXPECT_EQ(config.value().sensors[1].kind, "lidar");
  EXPECT_FALSE(config.value().sensors[1].semantic);
  EXPECT_EQ(config.value().sensors[1].providedLayers() & kProvidesObjects, 0u);
  EXPECT_EQ(config.value().plan, TeamPlan::kMeet);
}

TEST(Presets, TinyAndOverrides) {
  const SimulatedDataset tiny = plan("tiny");
  EXPECT_LE(tiny.sensed->world.rooms.size(), 6u);
  EXPECT_EQ(tiny.runs.size(), 2u);
  EXPECT_LT(totalPath(tiny), 120.0);

  const SimulatedDataset five = plan("office-3", 1, 5);
  EXPECT_EQ(five.runs.size(), 5u);
  auto small = presetConfig("dorm-2", 1, std::nullopt, 0.5);
  auto big = presetConfig("dorm-2", 1, std::nullopt, 2.0);
  ASSERT_TRUE(small.ok() && big.ok());
  EXPECT_EQ(big.value().building.rooms_per_side, 4 * small.value().building.rooms_per_side);
}

}  // namespace
}  // namespace hydra_multi::sim
