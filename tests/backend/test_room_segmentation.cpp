#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "hydra_multi/backend/room_segmentation.h"
#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/sim/dataset.h"

namespace hydra_multi {
namespace {

// Places on a 1 m grid at z = 1, joined to their grid neighbours by edges weighted by the smaller
// radius of their ends.
class PlaceGrid {
 public:
  void add(int x, int y, double radius) {
    Node p = makeNode(NodeId('p', next_++), Layer::kPlaces, Eigen::Vector3d(x, y, 1.0));
    p.find<PlaceAttributes>()->distance = radius;
    graph_.addOrUpdateNode(p);
    at_[{x, y}] = p.id;
  }
  SceneGraph connected() {
    for (const auto& [xy, id] : at_) {
      for (const auto& step : {std::make_pair(1, 0), std::make_pair(0, 1)}) {
        const auto other = at_.find({xy.first + step.first, xy.second + step.second});
        if (other == at_.end()) continue;
        const double w = std::min(graph_.getNode(id).find<PlaceAttributes>()->distance,
                                  graph_.getNode(other->second).find<PlaceAttributes>()->distance);
        graph_.addOrUpdateEdge(id, other->second, {w, true});
      }
    }
    return graph_;
  }

 private:
  SceneGraph graph_;
  uint64_t next_ = 0;
  std::map<std::pair<int, int>, NodeId> at_;
};

// Two 5 x 5 rooms of places 1 m apart (radius 1.0 inside, 0.5 next to walls), joined by a door
// of two places of radius 0.4 (or an opening of another radius).
SceneGraph twoRooms(double door_radius = 0.4) {
  PlaceGrid grid;
  for (const int x0 : {0, 7}) {
    for (int x = 0; x < 5; ++x)
      for (int y = 0; y < 5; ++y)
        grid.add(x0 + x, y, (x == 0 || y == 0 || x == 4 || y == 4) ? 0.5 : 1.0);
  }
  grid.add(5, 2, door_radius);
  grid.add(6, 2, door_radius);
  return grid.connected();
}

// The door splits the places into two rooms of 25 and 27 (the door places join the nearer
// room); each room's places are connected; rooms hang under one building.
TEST(RoomSegmentation, TwoRoomsSplitAtTheDoor) {
  SceneGraph g = twoRooms();
  RoomSegmentationOptions options;
  options.min_room_places = 5;
  const RoomSegmentation rooms = segmentRooms(g, options);
  ASSERT_EQ(rooms.rooms.size(), 2u);
  EXPECT_EQ(rooms.rooms[0].size() + rooms.rooms[1].size(), g.numNodes(Layer::kPlaces));
  for (const auto& room : rooms.rooms) {
    // Every place of a room is on one side of the door (x < 5.5 or x > 5.5).
    const bool left = g.getNode(room.front()).position.x() < 5.5;
    for (const NodeId p : room) EXPECT_EQ(g.getNode(p).position.x() < 5.5, left);
  }
  applyRooms(g, rooms);
  EXPECT_EQ(g.numNodes(Layer::kRooms), 2u);
  EXPECT_EQ(g.numNodes(Layer::kBuildings), 1u);
  for (const NodeId p : g.nodesInLayer(Layer::kPlaces)) {
    const auto parent = g.parent(p);
    ASSERT_TRUE(parent.has_value());
    EXPECT_EQ(g.getNode(*parent).layer(), Layer::kRooms);
  }
  for (const NodeId r : g.nodesInLayer(Layer::kRooms)) EXPECT_EQ(g.parent(r), NodeId('B', 0));
  // Applying again replaces, never adds.
  applyRooms(g, segmentRooms(g, options));
  EXPECT_EQ(g.numNodes(Layer::kRooms), 2u);
}

// Without places there are no rooms; a single open space is one room.
// Three small rooms of 3 x 2 places (radius 0.7) off a wide corridor of 10 x 2 (radius 1.1), each
// through a door place of radius 0.4: the small rooms stand apart only at thresholds 0.43-0.64 of
// 0.43-1.2, four seeds; above, the corridor alone (1), then nothing (0). The median count is 1:
// one room of everything (as on the dorm floors); the most seeds make the four rooms.
TEST(RoomSegmentation, SmallRoomsOffACorridorTakeTheMostSeedsRule) {
  PlaceGrid grid;
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 2; ++y) grid.add(x, y, 1.1);
  for (const int x0 : {0, 4, 8}) {
    grid.add(x0 + 1, 2, 0.4);  // the door
    for (int x = 0; x < 3; ++x)
      for (int y = 3; y < 5; ++y) grid.add(x0 + x, y, 0.7);
  }
  const SceneGraph g = grid.connected();
  RoomSegmentationOptions options;
  options.min_room_places = 5;
  options.rule = RoomSegmentationOptions::Rule::kMedian;
  EXPECT_EQ(segmentRooms(g, options).rooms.size(), 1u);
  options.rule = RoomSegmentationOptions::Rule::kMost;
  const RoomSegmentation rooms = segmentRooms(g, options);
  ASSERT_EQ(rooms.rooms.size(), 4u);
  EXPECT_LT(rooms.threshold, 0.7);
  size_t corridors = 0;
  for (const auto& room : rooms.rooms) {
    // A room is the corridor (y < 2) or one small room (y > 2), never both; a door place (y = 2)
    // joins either side, as near to both.
    size_t low = 0, high = 0;
    for (const NodeId p : room) {
      low += g.getNode(p).position.y() < 1.5;
      high += g.getNode(p).position.y() > 2.5;
    }
    EXPECT_TRUE(low == 0 || high == 0);
    EXPECT_EQ(low + high, low > 0 ? 20u : 6u);
    corridors += low > 0;
  }
  EXPECT_EQ(corridors, 1u);
}

// With the most seeds, an opening of radius 0.7 between the two rooms parts them too (at
// thresholds 0.7-1.0 of 0.43-1.2); it is wider than a door of max_door_radius 0.55, so they are
// one room. A door of 0.4 keeps them two.
TEST(RoomSegmentation, AnOpeningWiderThanADoorJoinsTwoRooms) {
  RoomSegmentationOptions options;
  options.min_room_places = 5;
  options.rule = RoomSegmentationOptions::Rule::kMost;
  options.max_door_radius = 0.0;
  EXPECT_EQ(segmentRooms(twoRooms(0.7), options).rooms.size(), 2u);
  options.max_door_radius = 0.55;
  const RoomSegmentation opening = segmentRooms(twoRooms(0.7), options);
  ASSERT_EQ(opening.rooms.size(), 1u);
  EXPECT_EQ(opening.rooms[0].size(), 52u);
  EXPECT_EQ(segmentRooms(twoRooms(0.4), options).rooms.size(), 2u);
}

TEST(RoomSegmentation, EmptyAndSingleRoom) {
  SceneGraph empty;
  EXPECT_TRUE(segmentRooms(empty).rooms.empty());
  SceneGraph g = twoRooms();
  for (const NodeId p : g.nodesInLayer(Layer::kPlaces))
    if (g.getNode(p).position.x() > 5.5) g.removeNode(p);
  RoomSegmentationOptions options;
  options.min_room_places = 5;
  EXPECT_EQ(segmentRooms(g, options).rooms.size(), 1u);
}

// Room segmentation of a simulated robot's own places (robot a, whose frame is the global frame;
// half scale): the defaults against DESIGN.md's rule (config/hydra-rooms.json).
struct SimulatedRooms {
  size_t true_rooms = 0;
  SceneGraphScore ours, design;
};
SimulatedRooms simulatedRooms(const std::string& preset) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() /
                       ("hydra_multi_test_rooms_" + preset + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  SimulatedRooms result;
  auto dataset = sim::simulateDataset(sim::presetConfig(preset, 1, 1, 0.5).value());
  EXPECT_TRUE(dataset.ok());
  if (!dataset.ok() || !sim::writeDataset(dataset.value(), dir.string()).ok()) return result;
  const DatasetGroundTruth truth = readDatasetGroundTruth(dir.string()).value();
  result.true_rooms = truth.room_ids.size();
  RoomSegmentationOptions design;
  design.min_room_places = 10;
  design.rule = RoomSegmentationOptions::Rule::kMedian;
  design.max_door_radius = 0.0;
  for (const auto& [options, score] : {std::make_pair(RoomSegmentationOptions{}, &result.ours),
                                       std::make_pair(design, &result.design)}) {
    SceneGraph graph = replayRobotGraph(truth, RobotId(0)).value().graph;
    applyRooms(graph, segmentRooms(graph, options));
    *score = evaluateSceneGraph(graph, truth);
  }
  fs::remove_all(dir);
  return result;
}

// The dorm floor's student rooms (8 places each): DESIGN.md's rule makes one room of the floor
// (measured: precision 0.39), ours separates them (16 rooms of the 19, precision 0.94); the
// recall, bounded by how much of each room the places cover, stays (0.47 against 0.49).
TEST(RoomSegmentation, SimulatedDormRooms) {
  const SimulatedRooms rooms = simulatedRooms("dorm-2");
  EXPECT_EQ(rooms.design.num_rooms, 1u);
  EXPECT_LT(rooms.design.rooms_precision.value_or(1.0), 0.5);
  EXPECT_GE(rooms.ours.num_rooms, rooms.true_rooms / 2);
  EXPECT_LE(rooms.ours.num_rooms, rooms.true_rooms);
  EXPECT_GT(rooms.ours.rooms_precision.value_or(0.0), 0.9);
  EXPECT_GT(rooms.ours.rooms_recall.value_or(0.0), 0.4);
}

// An office's large rooms: both rules find them roughly (measured: ours 12 rooms of 7, precision
// 0.89, recall 0.42; DESIGN.md's 5, 0.88, 0.48; recall counts the rooms the robot never entered).
// On half a building seen by one robot ours splits more; the five seeds of the whole team find
// 8-16 rooms of 12, precision 0.95 and recall 0.77 against 0.94 and 0.73 (README, `trials`).
TEST(RoomSegmentation, SimulatedOfficeRooms) {
  const SimulatedRooms rooms = simulatedRooms("office-3");
  EXPECT_GE(rooms.ours.num_rooms, 3u);
  EXPECT_LE(rooms.ours.num_rooms, 2 * rooms.true_rooms);
  EXPECT_GT(rooms.ours.rooms_precision.value_or(0.0), 0.8);
  EXPECT_GT(rooms.ours.rooms_recall.value_or(0.0), 0.35);
}

}  // namespace
}  // namespace hydra_multi
