#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/exploration.h"
#include "hydra_multi/sim/places.h"

namespace hydra_multi::sim {
namespace {

// A robot that only looked around in room 1 knows places in room 1 (and around its door), none in
// rooms it could not see; every place is an explored GVD cell with its clearance as radius, at
// most one per spacing square; edges are short, free, and no wider than their ends.
TEST(Places, FromWhatTheRobotSaw) {
  BuildingOptions options;
  options.rooms_per_side = 4;
  const World world = generateBuilding(options).value();
  const FreeSpace space = computeFreeSpace(world);
  const FloorGrid& g = space.floors[0];
  const auto start = roomStandpoint(g, 1);
  ASSERT_TRUE(start.ok());
  auto tour = planRoomTour(world, g, start.value(), {1});
  ASSERT_TRUE(tour.ok()) << tour.error();
  PlacesOptions places_options;
  const PlaceGraph graph = extractPlaces(g, tour.value(), places_options);
  ASSERT_GE(graph.places.size(), 3u);
  std::set<std::pair<int, int>> squares;
  std::set<int> rooms;
  for (const PlaceGraph::Place& p : graph.places) {
    const Eigen::Vector2i c = g.cellOf(p.position.head<2>());
    const size_t i = g.index(c.x(), c.y());
    EXPECT_TRUE(g.gvd[i]);
    EXPECT_NEAR(p.distance, g.clearance[i], 1e-6);
    EXPECT_GE(p.distance, 0.3);
    EXPECT_DOUBLE_EQ(p.position.z(), 1.0);
    EXPECT_TRUE(squares
                    .insert({static_cast<int>(std::floor(p.position.x())),
                             static_cast<int>(std::floor(p.position.y()))})
                    .second);
    rooms.insert(p.room);
  }
  EXPECT_TRUE(rooms.count(1));
  for (const int r : {2, 3, 4, 6, 7, 8})
    EXPECT_FALSE(rooms.count(r)) << "room " << r << " was never seen";
  ASSERT_FALSE(graph.edges.empty());
  for (const PlaceGraph::Edge& e : graph.edges) {
    const auto& a = graph.places[e.a];
    const auto& b = graph.places[e.b];
    EXPECT_LE((a.position - b.position).norm(), places_options.max_edge_length + 1e-9);
    EXPECT_LE(e.weight, std::min(a.distance, b.distance) + 1e-6);
    EXPECT_GT(e.weight, 0.0);
  }
  EXPECT_TRUE(extractPlaces(g, {}).places.empty());
}

}  // namespace
}  // namespace hydra_multi::sim
