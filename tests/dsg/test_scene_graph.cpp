#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "hydra_multi/dsg/graph_summary.h"
#include "hydra_multi/dsg/scene_graph.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

const NodeId kBuilding('B', 0), kRoom('R', 0), kRoom2('R', 1), kPlace1('p', 1), kPlace2('p', 2),
    kObject1('O', 1), kObject2('O', 2), kAgent0('a', 0), kAgent1('a', 1);

SceneGraph smallGraph() {
  SceneGraph g;
  g.addOrUpdateNode(makeNode(kBuilding, Layer::kBuildings));
  g.addOrUpdateNode(makeNode(kRoom, Layer::kRooms));
  g.addOrUpdateNode(makeNode(kRoom2, Layer::kRooms));
  g.addOrUpdateNode(makeNode(kPlace1, Layer::kPlaces, {0, 0, 1}));
  g.addOrUpdateNode(makeNode(kPlace2, Layer::kPlaces, {2, 0, 1}));
  g.addOrUpdateNode(makeNode(kObject1, Layer::kObjects, {0, 1, 1}));
  g.addOrUpdateNode(makeNode(kAgent0, Layer::kAgents));
  g.addOrUpdateNode(makeNode(kAgent1, Layer::kAgents));
  g.addOrUpdateEdge(kBuilding, kRoom);
  g.addOrUpdateEdge(kRoom, kPlace1);
  g.addOrUpdateEdge(kPlace1, kPlace2, {1.5, true});
  g.addOrUpdateEdge(kPlace1, kObject1);
  g.addOrUpdateEdge(kAgent0, kAgent1);
  g.addOrUpdateEdge(kPlace2, kAgent1);
  return g;
}

TEST(SceneGraph, AddUpdateAndQuery) {
  SceneGraph g = smallGraph();
  EXPECT_EQ(g.numNodes(), 8u);
  EXPECT_EQ(g.numEdges(), 6u);
  EXPECT_EQ(g.numNodes(Layer::kPlaces), 2u);
  EXPECT_EQ(g.parent(kPlace1), kRoom);
  EXPECT_EQ(g.parent(kRoom), kBuilding);
  EXPECT_FALSE(g.parent(kBuilding).has_value());
  EXPECT_EQ(g.children(kPlace1), std::vector<NodeId>{kObject1});
  EXPECT_EQ(g.neighbours(kPlace1), std::vector<NodeId>{kPlace2});
  EXPECT_EQ(g.findEdge(kPlace1, kPlace2)->weight, 1.5);
  EXPECT_EQ(g.findEdge(kPlace2, kPlace1)->weight, 1.5);  // undirected
  EXPECT_EQ(g.nodesOfRobot(RobotId(0)), (std::vector<NodeId>{kAgent0, kAgent1}));
  EXPECT_EQ(g.robots(), std::vector<RobotId>{RobotId(0)});

  // Updating keeps edges; the second add returns false.
  Node moved = g.getNode(kPlace1);
  moved.position = {5, 5, 5};
  EXPECT_FALSE(g.addOrUpdateNode(moved));
  EXPECT_EQ(g.getNode(kPlace1).position, Eigen::Vector3d(5, 5, 5));
  EXPECT_TRUE(g.hasEdge(kPlace1, kPlace2));
}

TEST(SceneGraph, RejectsMisuse) {
  SceneGraph g = smallGraph();
  EXPECT_THROW(g.addOrUpdateNode(makeNode(kPlace1, Layer::kObjects)), std::invalid_argument);
  EXPECT_THROW(g.addOrUpdateEdge(kPlace1, NodeId('p', 99)), std::invalid_argument);
  EXPECT_THROW(g.addOrUpdateEdge(kPlace1, kPlace1), std::invalid_argument);
  EXPECT_THROW(g.addOrUpdateEdge(kAgent0, kObject1), std::invalid_argument);  // same level
  EXPECT_THROW((void)g.getNode(NodeId('p', 99)), std::out_of_range);
  EXPECT_EQ(g.findNode(NodeId('p', 99)), nullptr);
}

// A node has one parent: a new parent edge replaces the old one.
TEST(SceneGraph, SingleParent) {
  SceneGraph g = smallGraph();
  g.addOrUpdateEdge(kRoom2, kPlace1);
  EXPECT_EQ(g.parent(kPlace1), kRoom2);
  EXPECT_FALSE(g.hasEdge(kRoom, kPlace1));
  EXPECT_TRUE(g.children(kRoom).empty());
}

TEST(SceneGraph, RemoveNodeTakesItsEdges) {
  SceneGraph g = smallGraph();
  EXPECT_TRUE(g.removeNode(kPlace1));
  EXPECT_FALSE(g.removeNode(kPlace1));
  EXPECT_EQ(g.numEdges(), 3u);
  EXPECT_TRUE(g.neighbours(kPlace2).empty());
  EXPECT_FALSE(g.parent(kObject1).has_value());
  EXPECT_TRUE(g.removeEdge(kAgent0, kAgent1));
  EXPECT_FALSE(g.removeEdge(kAgent0, kAgent1));
}

TEST(SceneGraph, CopyIsIndependent) {
  SceneGraph g = smallGraph();
  SceneGraph copy = g;
  EXPECT_EQ(copy, g);
  copy.removeNode(kPlace2);
  EXPECT_NE(copy, g);
  EXPECT_TRUE(g.hasNode(kPlace2));
  EXPECT_TRUE(g.hasEdge(kPlace1, kPlace2));
}

// Merging moves edges and fuses attributes; undo restores the graph exactly.
TEST(SceneGraph, MergeAndUndo) {
  SceneGraph g = smallGraph();
  Node o2 = makeNode(kObject2, Layer::kObjects, {2, 1, 1});
  o2.find<ObjectAttributes>()->mesh_vertices = {7, 3};
  o2.find<ObjectAttributes>()->semantic.bounding_box = BoundingBox{{1, 1, 1}, {3, 3, 3}};
  g.addOrUpdateNode(o2);
  g.addOrUpdateEdge(kPlace2, kObject2);
  Node o1 = g.getNode(kObject1);
  o1.find<ObjectAttributes>()->mesh_vertices = {3, 5};
  o1.find<ObjectAttributes>()->semantic.bounding_box = BoundingBox{{0, 0, 0}, {2, 2, 2}};
  g.addOrUpdateNode(o1);
  const SceneGraph before = g;

  MergeRecord record;
  g.mergeNodes(kObject1, kObject2, &record);
  EXPECT_FALSE(g.hasNode(kObject2));
  const Node& merged = g.getNode(kObject1);
  EXPECT_EQ(merged.position, Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(merged.find<ObjectAttributes>()->mesh_vertices, (std::vector<uint64_t>{3, 5, 7}));
  EXPECT_EQ(merged.find<ObjectAttributes>()->semantic.bounding_box,
            (BoundingBox{{0, 0, 0}, {3, 3, 3}}));
  EXPECT_EQ(g.parent(kObject1), kPlace1);  // the target keeps its own parent

  ASSERT_TRUE(g.undoMerge(record).ok());
  EXPECT_EQ(g, before);
  // Undoing twice fails: the source exists again.
  EXPECT_FALSE(g.undoMerge(record).ok());
}

// The per-robot and per-layer queries answer what a pass over every node answers, and every edge is
// found as the graph's own, through adds, removals, merges and their undo, in a copy and after a
// move (removals there go through the index the copy or the move left).
TEST(SceneGraph, RobotAndLayerQueriesFollowEveryChange) {
  const auto check = [](const SceneGraph& g) {
    std::map<RobotId, std::vector<NodeId>> of_robot;
    std::map<std::pair<RobotId, Layer>, std::vector<NodeId>> of_robot_in_layer;
    std::map<Layer, std::vector<NodeId>> in_layer;
    for (const auto& [id, node] : g.nodes()) {
      // Found by id as the graph's own node (a copy's lookups never reach the original).
      EXPECT_EQ(g.findNode(id), &node) << id.str();
      if (const auto robot = node.robot()) {
        of_robot[*robot].push_back(id);
        of_robot_in_layer[{*robot, node.layer()}].push_back(id);
      }
      in_layer[node.layer()].push_back(id);
    }
    for (const auto& [key, info] : g.edges()) {
      EXPECT_EQ(g.findEdge(key.second(), key.first()), &info);
      EXPECT_TRUE(g.hasEdge(key.first(), key.second()));
      EXPECT_TRUE(g.findNode(key.first()) && g.findNode(key.second()));
    }
    for (const char prefix : {'a', 'b', 'c'}) {
      const RobotId robot = *RobotId::fromPrefix(prefix);
      EXPECT_EQ(g.nodesOfRobot(robot), of_robot[robot]) << prefix;
      std::vector<const Node*> own;  // the graph's own nodes (a copy's never the original's)
      for (const NodeId id : of_robot[robot]) own.push_back(&g.nodes().at(id));
      EXPECT_EQ(g.robotNodes(robot), own) << prefix;
      for (const Layer layer : kAllLayers) {
        EXPECT_EQ(g.nodesOfRobot(robot, layer), (of_robot_in_layer[{robot, layer}]))
            << prefix << " " << layerName(layer);
        EXPECT_EQ(g.numNodes(robot, layer), (of_robot_in_layer[{robot, layer}].size()))
            << prefix << " " << layerName(layer);
      }
    }
    for (const Layer layer : kAllLayers) {
      EXPECT_EQ(g.nodesInLayer(layer), in_layer[layer]) << layerName(layer);
      EXPECT_EQ(g.numNodes(layer), in_layer[layer].size()) << layerName(layer);
    }
    std::set<RobotId> robots;
    for (const auto& [robot, ids] : of_robot) robots.insert(robot);
    for (const MeshVertex& v : g.mesh().vertices) robots.insert(v.robot);
    EXPECT_EQ(g.robots(), std::vector<RobotId>(robots.begin(), robots.end()));
  };
  std::mt19937 rng(11);
  SceneGraph g = testing::makeRandomGraph(rng);
  check(g);
  const RobotId b = *RobotId::fromPrefix('b');
  const NodeId o1 = NodeId::station('O', b, 1), o2 = NodeId::station('O', b, 2);
  g.addOrUpdateNode(makeNode(o1, Layer::kObjects, {0, 0, 0}));
  g.addOrUpdateNode(makeNode(o2, Layer::kObjects, {1, 0, 0}));
  g.addOrUpdateNode(makeNode(NodeId('c', 3), Layer::kAgents));
  check(g);
  MergeRecord record;
  g.mergeNodes(o1, o2, &record);
  check(g);
  ASSERT_TRUE(g.undoMerge(record).ok());
  check(g);
  for (const NodeId id : g.nodesInLayer(Layer::kAgents)) {
    if (id.index() % 2 == 0) g.removeNode(id);
  }
  EXPECT_TRUE(g.removeNode(NodeId('c', 3)));
  check(g);
  const SceneGraph copy = g;
  check(copy);
  SceneGraph assigned;
  assigned = copy;
  g = SceneGraph();  // the copies outlive what they were copied from
  check(assigned);
  EXPECT_FALSE(assigned.findNode(NodeId('c', 3)));
  EXPECT_EQ(assigned, copy);
  const auto remove_some = [](SceneGraph& graph, size_t every) {
    std::vector<NodeId> ids;
    for (const auto& [id, node] : graph.nodes()) ids.push_back(id);
    size_t removed = 0;
    for (size_t i = 0; i < ids.size(); i += every) removed += graph.removeNode(ids[i]);
    return removed;
  };
  ASSERT_GT(remove_some(assigned, 3), 0u);
  check(assigned);
  check(copy);
  EXPECT_NE(assigned, copy);
  SceneGraph moved = std::move(assigned);
  ASSERT_GT(remove_some(moved, 2), 0u);
  check(moved);
  ASSERT_FALSE(moved.nodes().empty());
  const NodeId first = moved.nodes().begin()->first;
  const size_t edges = moved.numEdges(), its_edges = moved.adjacent(first).size();
  EXPECT_TRUE(moved.removeNode(first));
  EXPECT_EQ(moved.numEdges(), edges - its_edges);
  check(moved);
}

// The source's children move to the target, and go back on undo.
TEST(SceneGraph, MergeMovesChildren) {
  SceneGraph g = smallGraph();
  const SceneGraph before = g;
  MergeRecord record;
  g.mergeNodes(kPlace1, kPlace2, &record);
  EXPECT_EQ(g.parent(kAgent1), kPlace1);
  EXPECT_FALSE(g.hasEdge(kPlace1, kPlace2));
  ASSERT_TRUE(g.undoMerge(record).ok());
  EXPECT_EQ(g, before);
  EXPECT_THROW(g.mergeNodes(kAgent0, kAgent1), std::invalid_argument);
  EXPECT_THROW(g.mergeNodes(kPlace1, kObject1), std::invalid_argument);
}

TEST(GraphSummary, CountsPerLayerAndRobot) {
  std::mt19937 rng(1);
  const SceneGraph g = testing::makeRandomGraph(rng);
  const GraphSummary s = summarize(g);
  EXPECT_EQ(s.nodes, g.numNodes());
  EXPECT_EQ(s.nodes_per_layer[static_cast<size_t>(Layer::kAgents)], 20u);
  EXPECT_EQ(s.nodes_per_layer[static_cast<size_t>(Layer::kPlaces)], 30u);
  EXPECT_EQ(s.robots.at(RobotId(0)).nodes_per_layer[0] + s.robots.at(RobotId(1)).nodes_per_layer[0],
            20u);
  size_t mesh_total = 0;
  for (const auto& [robot, r] : s.robots) mesh_total += r.mesh_vertices;
  EXPECT_EQ(mesh_total, 200u);
}

}  // namespace
}  // namespace hydra_multi
