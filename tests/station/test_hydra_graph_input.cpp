// A Hydra robot's whole graphs as robot updates (station/hydra_graph_input.h): what the station
// gets from them is the robot's graph, and what it derives (odometry, control points, bags of
// words) is what our robots send, for a simulated robot speaking as Hydra; corrections go whole;
// bad graphs change nothing.

#include <gtest/gtest.h>

#include <cmath>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/io/spark_graph.h"
#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/sim/dataset.h"
#include "hydra_multi/sim/presets.h"
#include "hydra_multi/station/hydra_graph_input.h"

namespace hydra_multi {
namespace {

const RobotId kA(0), kB(1);

std::vector<RobotUpdate> tinyStream(size_t robot) {
  const sim::SimulatedDataset dataset =
      sim::simulateDataset(sim::presetConfig("tiny", 1).value()).value();
  return dataset.streams.at(robot);
}

// What the robot would publish after this update, through the wire form and back.
io::spark::Graph published(const RobotStreamState& state) {
  const io::spark::Graph graph = hydraGraphOfMap(state.snapshot()).value();
  return io::spark::decodeWire(io::spark::encodeWire(graph)).value();
}

// A hand-made Hydra graph: agents a0..a2 along x, a place and an object, a three-vertex mesh.
io::spark::Graph handMade(char prefix = 'a') {
  io::spark::Graph g;
  g.node_types = io::spark::knownNodeTypes();
  g.edge_types = {"EdgeAttributes"};
  g.layer_keys = {{2, 0}, {2, static_cast<uint32_t>(prefix)}, {3, 0}};
  const auto type = [&g](const std::string& name) {
    return static_cast<uint8_t>(std::find(g.node_types.begin(), g.node_types.end(), name) -
                                g.node_types.begin());
  };
  for (uint64_t k = 0; k < 3; ++k) {
    io::spark::Node n;
    n.layer = 2;
    n.partition = static_cast<uint32_t>(prefix);
    n.id = NodeId(prefix, k).value();
    n.attributes.type = "AgentNodeAttributes";
    n.type_id = type(n.attributes.type);
    n.attributes.position = {double(k), 0.0, 0.0};
    n.attributes.timestamp_ns = int64_t(k + 1) * 1000000000;
    n.attributes.dbow_ids = {1, 1, 0xce, {double(7 + k)}};
    n.attributes.dbow_values = {1, 1, 0xca, {0.5}};
    g.nodes.push_back(n);
  }
  io::spark::Node place;
  place.layer = 3;
  place.id = NodeId('p', 0).value();
  place.attributes.type = "PlaceNodeAttributes";
  place.type_id = type(place.attributes.type);
  place.attributes.distance = 1.0;
  place.attributes.pcl_mesh_connections = {0, 1};
  g.nodes.push_back(place);
  io::spark::Node object;
  object.layer = 2;
  object.id = NodeId('O', 0).value();
  object.attributes.type = "ObjectNodeAttributes";
  object.type_id = type(object.attributes.type);
  object.attributes.mesh_connections = {1, 2};
  g.nodes.push_back(object);
  for (uint64_t k = 0; k + 1 < 3; ++k) {
    io::spark::Edge e;
    e.source = NodeId(prefix, k).value();
    e.target = NodeId(prefix, k + 1).value();
    e.attributes.type = "EdgeAttributes";
    g.edges.push_back(e);
  }
  io::spark::Mesh mesh;
  mesh.has_stamps = true;
  mesh.points = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}};
  mesh.stamps = {1000000000, 2500000000, 3500000000};
  mesh.faces = {{0, 1, 2}};
  g.mesh = mesh;
  return g;
}

TEST(HydraGraphInput, SimulatedRobotSpeakingHydraGivesItsGraphAndWhatItDerives) {
  const std::vector<RobotUpdate> stream = tinyStream(0);
  ASSERT_GT(stream.size(), 3u);
  RobotStreamState robot, station;
  HydraGraphInput input(kA);
  std::vector<PoseGraphEdge> odometry, derived_odometry;
  DeformationGraphDelta control, derived_control;
  std::map<NodeId, std::vector<BowEntry>> bow, derived_bow;
  size_t snapshots = 0;
  for (const RobotUpdate& u : stream) {
    ASSERT_TRUE(robot.add(u).ok());
    for (const PoseGraphEdge& e : u.pose_graph)
      if (e.kind == PoseGraphEdge::Kind::kOdometry) odometry.push_back(e);
    control.points.insert(control.points.end(), u.deformation.points.begin(),
                          u.deformation.points.end());
    control.edges.insert(control.edges.end(), u.deformation.edges.begin(),
                         u.deformation.edges.end());
    for (const KeyframeDescriptor& d : u.descriptors) bow[d.keyframe] = d.bow;

    const io::spark::Graph graph = published(robot);
    HydraGraphNotes notes;
    auto taken = input.take(graph, &notes);
    ASSERT_TRUE(taken.ok()) << taken.error();
    ASSERT_TRUE(taken.value().has_value()) << "update " << u.sequence << " changed the map";
    const RobotUpdate& update = *taken.value();
    EXPECT_EQ(update.sequence, u.sequence);
    EXPECT_EQ(update.time_ns, u.time_ns);
    EXPECT_FALSE(notes.agent_prefix);
    EXPECT_TRUE(notes.correction.empty()) << notes.correction;
    snapshots += update.is_snapshot ? 1 : 0;
    ASSERT_TRUE(station.add(update).ok());
    // The station's copy of the robot's graph is the graph the robot published, exactly.
    EXPECT_EQ(graphFromSnapshot(station.snapshot().graph).value(),
              io::sceneGraphFromSpark(graph).value().graph);
    derived_odometry.insert(derived_odometry.end(), update.pose_graph.begin(),
                            update.pose_graph.end());
    derived_control.points.insert(derived_control.points.end(), update.deformation.points.begin(),
                                  update.deformation.points.end());
    derived_control.edges.insert(derived_control.edges.end(), update.deformation.edges.begin(),
                                 update.deformation.edges.end());
    for (const KeyframeDescriptor& d : update.descriptors) {
      EXPECT_TRUE(d.keypoints.empty());
      derived_bow[d.keyframe] = d.bow;
    }
  }
  EXPECT_EQ(snapshots, 1u);
  // The node ids, positions and layers of the robot's own map (boxes go through float).
  const SceneGraph own = graphFromSnapshot(robot.snapshot().graph).value();
  const SceneGraph got = input.graph();
  ASSERT_EQ(got.numNodes(), own.numNodes());
  for (const auto& [id, node] : own.nodes()) {
    const Node* other = got.findNode(id);
    ASSERT_NE(other, nullptr) << id.str();
    EXPECT_EQ(other->position, node.position) << id.str();
    EXPECT_EQ(other->layer(), node.layer()) << id.str();
  }
  EXPECT_EQ(got.edges(), own.edges());
  EXPECT_EQ(got.mesh(), own.mesh());
  // Odometry from consecutive keyframes: the robot's own, to rounding.
  ASSERT_EQ(derived_odometry.size(), odometry.size());
  for (size_t i = 0; i < odometry.size(); ++i) {
    EXPECT_EQ(derived_odometry[i].from, odometry[i].from);
    EXPECT_EQ(derived_odometry[i].to, odometry[i].to);
    EXPECT_LT((derived_odometry[i].T_from_to.matrix() - odometry[i].T_from_to.matrix())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-9);
  }
  // Control points from the mesh: the robot's own deformation graph.
  // (The robot's positions may carry its vertex before the float rounding: 1e-7 m.)
  ASSERT_EQ(derived_control.points.size(), control.points.size());
  for (size_t i = 0; i < control.points.size(); ++i) {
    const ControlPoint& d = derived_control.points[i];
    const ControlPoint& c = control.points[i];
    EXPECT_EQ(d.id, c.id);
    EXPECT_LT((d.position - c.position).norm(), 1e-6) << "control point " << i;
    EXPECT_EQ(d.time_ns, c.time_ns) << "control point " << i;
    EXPECT_EQ(d.keyframe, c.keyframe) << "control point " << i;
  }
  EXPECT_EQ(derived_control.edges, control.edges);
  EXPECT_EQ(derived_bow, bow);
}

TEST(HydraGraphInput, AgentsTakeTheRobotsPrefixAndWhatCannotBeUsedIsLeftOut) {
  io::spark::Graph graph = handMade('a');
  io::spark::Node frontier = graph.nodes[3];  // a copy of the place, not real
  frontier.id = NodeId('f', 4).value();
  frontier.attributes.real_place = false;
  graph.nodes.push_back(frontier);
  graph.nodes[4].attributes.mesh_connections = {1, 2, 99};  // the object: vertex 99 is no vertex
  HydraGraphInput input(kB);
  HydraGraphNotes notes;
  auto taken = input.take(graph, &notes);
  ASSERT_TRUE(taken.ok()) << taken.error();
  const RobotUpdate& u = taken.value().value();
  EXPECT_TRUE(u.is_snapshot);
  EXPECT_EQ(u.robot, kB);
  EXPECT_EQ(u.sequence, 0u);
  EXPECT_EQ(u.time_ns, 3000000000);
  ASSERT_TRUE(notes.agent_prefix.has_value());
  EXPECT_EQ(*notes.agent_prefix, 'a');
  EXPECT_EQ(notes.left_out.at("frontiers (places not real)"), 1u);
  EXPECT_EQ(notes.left_out.at("mesh vertex indices past the mesh"), 1u);
  const SceneGraph& g = input.graph();
  EXPECT_TRUE(g.hasNode(NodeId('b', 2)));
  EXPECT_FALSE(g.hasNode(NodeId('a', 2)));
  EXPECT_FALSE(g.hasNode(NodeId('f', 4)));
  EXPECT_TRUE(g.hasEdge(NodeId('b', 0), NodeId('b', 1)));
  EXPECT_EQ(g.getNode(NodeId('O', 0)).find<ObjectAttributes>()->mesh_vertices,
            (std::vector<uint64_t>{1, 2}));
  for (const MeshVertex& v : g.mesh().vertices) EXPECT_EQ(v.robot, kB);
  // Odometry a0 -> a1 -> a2 as b's, one step of 1 m each.
  ASSERT_EQ(u.pose_graph.size(), 2u);
  EXPECT_EQ(u.pose_graph[1].from, NodeId('b', 1));
  EXPECT_EQ(u.pose_graph[1].to, NodeId('b', 2));
  EXPECT_TRUE(u.pose_graph[1].T_from_to.translation().isApprox(Eigen::Vector3d(1, 0, 0)));
  // Control points: each vertex lies in a 2.5 m voxel of its own ((0,0,0), (1,0,0), (0,1,0),
  // all neighbours), attached to the keyframe of its stamp (1 s, 2.5 s, 3.5 s: b0, b1, b2).
  ASSERT_EQ(u.deformation.points.size(), 3u);
  EXPECT_EQ(u.deformation.points[0].keyframe, NodeId('b', 0));
  EXPECT_EQ(u.deformation.points[1].keyframe, NodeId('b', 1));
  EXPECT_EQ(u.deformation.points[2].keyframe, NodeId('b', 2));
  EXPECT_EQ(u.deformation.edges, (std::vector<ControlPointEdge>{{0, 1}, {0, 2}, {1, 2}}));
  ASSERT_EQ(u.descriptors.size(), 3u);
  EXPECT_EQ(u.descriptors[2].keyframe, NodeId('b', 2));
  EXPECT_EQ(u.descriptors[2].bow, (std::vector<BowEntry>{{9, 0.5f}}));
  EXPECT_TRUE(validateRobotUpdate(u).ok());
}

TEST(HydraGraphInput, TheSameGraphAgainIsNoUpdateAndGrowthIsADelta) {
  HydraGraphInput input(kA);
  ASSERT_TRUE(input.take(handMade()).value().has_value());
  auto again = input.take(handMade());
  ASSERT_TRUE(again.ok());
  EXPECT_FALSE(again.value().has_value());
  io::spark::Graph grown = handMade();
  io::spark::Node k3 = grown.nodes[2];
  k3.id = NodeId('a', 3).value();
  k3.attributes.position = {3, 0, 0};
  k3.attributes.timestamp_ns = 4000000000;
  grown.nodes.insert(grown.nodes.begin() + 3, k3);
  grown.mesh->points.push_back({6, 0, 0});
  grown.mesh->stamps.push_back(4000000000);
  auto taken = input.take(grown);
  ASSERT_TRUE(taken.ok()) << taken.error();
  const RobotUpdate& u = taken.value().value();
  EXPECT_FALSE(u.is_snapshot);
  EXPECT_EQ(u.sequence, 1u);  // the unchanged graph used no number
  ASSERT_EQ(u.graph.nodes.size(), 1u);
  EXPECT_EQ(u.graph.nodes[0].id, NodeId('a', 3));
  EXPECT_EQ(u.graph.mesh.vertex_start, 3u);
  ASSERT_EQ(u.pose_graph.size(), 1u);
  EXPECT_EQ(u.pose_graph[0].from, NodeId('a', 2));
  ASSERT_EQ(u.deformation.points.size(), 1u);
  EXPECT_EQ(u.deformation.points[0].id, 3u);
  EXPECT_EQ(u.deformation.points[0].keyframe, NodeId('a', 3));
  ASSERT_EQ(u.descriptors.size(), 1u);
}

TEST(HydraGraphInput, ARobotThatCorrectsItsMapIsTakenWhole) {
  HydraGraphInput input(kA);
  ASSERT_TRUE(input.take(handMade()).ok());
  io::spark::Graph corrected = handMade();
  corrected.nodes[1].attributes.position = {1.0, 0.2, 0.0};  // a1 moved by the robot's loop closure
  HydraGraphNotes notes;
  auto taken = input.take(corrected, &notes);
  ASSERT_TRUE(taken.ok());
  const RobotUpdate& u = taken.value().value();
  EXPECT_TRUE(u.is_snapshot);
  EXPECT_EQ(notes.correction, "the odometry a0 -> a1 moved");
  EXPECT_EQ(u.pose_graph.size(), 2u);          // derived anew
  EXPECT_EQ(u.deformation.points.size(), 3u);  // likewise
  EXPECT_EQ(u.descriptors.size(), 3u);
  EXPECT_TRUE(u.pose_graph[0].T_from_to.translation().isApprox(Eigen::Vector3d(1, 0.2, 0)));

  io::spark::Graph moved_mesh = corrected;
  moved_mesh.mesh->points[1] = {3.0f, 0.5f, 0.0f};
  ASSERT_TRUE(input.take(moved_mesh, &notes).value().value().is_snapshot);
  EXPECT_EQ(notes.correction, "mesh vertex 1 changed");
}

TEST(HydraGraphInput, AGraphThatCannotBeUsedChangesNothing) {
  HydraGraphInput input(kA);
  ASSERT_TRUE(input.take(handMade()).ok());
  io::spark::Graph two_robots = handMade();
  io::spark::Node other = two_robots.nodes[0];
  other.id = NodeId('c', 0).value();
  other.partition = 'c';
  two_robots.nodes.push_back(other);
  auto refused = input.take(two_robots);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error(),
            "agents of several prefixes ('a', 'c'): a Hydra robot sends its own keyframes only");
  io::spark::Graph station_bit = handMade();
  station_bit.nodes[3].id |= NodeId::kStationBit;
  ASSERT_FALSE(input.take(station_bit).ok());
  // The next good graph is taken against the last good one: unchanged.
  auto next = input.take(handMade());
  ASSERT_TRUE(next.ok());
  EXPECT_FALSE(next.value().has_value());
  EXPECT_EQ(input.nextSequence(), 1u);
}

TEST(HydraGraphInput, AfterAResumeTheNextGraphGoesWholeWithTheGivenNumber) {
  HydraGraphInput input(kA);
  input.resumeAt(41);
  auto taken = input.take(handMade());
  ASSERT_TRUE(taken.ok());
  EXPECT_TRUE(taken.value()->is_snapshot);
  EXPECT_EQ(taken.value()->sequence, 41u);
  input.resumeAt(42);
  taken = input.take(handMade());  // the same graph, but the station asked for it whole
  ASSERT_TRUE(taken.value().has_value());
  EXPECT_TRUE(taken.value()->is_snapshot);
  EXPECT_EQ(taken.value()->sequence, 42u);
}

TEST(HydraGraphInput, BagsOfWordsWhoseArraysDisagreeAreLeftOutAndCounted) {
  io::spark::Graph graph = handMade();
  graph.nodes[0].attributes.dbow_values.values.push_back(0.25);
  graph.nodes[0].attributes.dbow_values.rows = 2;
  HydraGraphInput input(kA);
  HydraGraphNotes notes;
  auto taken = input.take(graph, &notes);
  ASSERT_TRUE(taken.ok());
  EXPECT_EQ(notes.bow_refused, 1u);
  EXPECT_EQ(taken.value()->descriptors.size(), 2u);
}

TEST(HydraGraphInput, TheApartmentFromSparkDsgIsTakenAsIs) {
  // Spark-DSG's own file of a real Hydra graph: its agents a, 7 objects, 185 places; the mesh
  // the file does not hold is what its objects' and places' vertex indices point past.
  const std::string path = std::string(HYDRA_MULTI_DATA_DIR) + "/spark/apartment.sparkdsg";
  auto bytes = io::readFile(path);
  ASSERT_TRUE(bytes.ok()) << bytes.error();
  const io::spark::Graph graph = io::spark::decodeFile(bytes.value()).value();
  HydraGraphInput input(kA);
  HydraGraphNotes notes;
  auto taken = input.take(graph, &notes);
  ASSERT_TRUE(taken.ok()) << taken.error();
  EXPECT_FALSE(notes.agent_prefix);
  const SceneGraph& g = input.graph();
  EXPECT_EQ(g.numNodes(Layer::kAgents), 102u);
  EXPECT_EQ(g.numNodes(Layer::kObjects), 7u);
  EXPECT_EQ(g.numNodes(Layer::kPlaces), 185u);
  EXPECT_EQ(taken.value()->pose_graph.size(), 101u);
  EXPECT_TRUE(taken.value()->deformation.points.empty());  // no mesh
  EXPECT_GT(notes.left_out.at("mesh vertex indices past the mesh"), 0u);
  EXPECT_TRUE(validateRobotUpdate(*taken.value()).ok());
}

TEST(HydraGraphInput, MoveTurnsAndShiftsEveryPartOfAGraph) {
  io::spark::Graph graph = handMade();
  graph.nodes[4].attributes.bounding_box.type = 1;
  graph.nodes[4].attributes.bounding_box.dimensions = {2.0f, 1.0f, 1.0f};
  graph.nodes[4].attributes.bounding_box.center = {1.0f, 0.0f, 0.0f};
  io::moveSparkGraph(graph, {10, 0, 1}, M_PI / 2);
  const auto& a1 = graph.nodes[1].attributes;
  EXPECT_NEAR(a1.position[0], 10.0, 1e-12);
  EXPECT_NEAR(a1.position[1], 1.0, 1e-12);
  EXPECT_NEAR(a1.position[2], 1.0, 1e-12);
  EXPECT_NEAR(a1.world_R_body[0], std::cos(M_PI / 4), 1e-12);  // w of a quarter turn about z
  EXPECT_NEAR(a1.world_R_body[3], std::sin(M_PI / 4), 1e-12);
  const auto& box = graph.nodes[4].attributes.bounding_box;
  EXPECT_NEAR(box.center[0], 10.0f, 1e-5);
  EXPECT_NEAR(box.center[1], 1.0f, 1e-5);
  EXPECT_NEAR(box.dimensions[0], 1.0f, 1e-5);  // the turned box: x and y swap
  EXPECT_NEAR(box.dimensions[1], 2.0f, 1e-5);
  EXPECT_NEAR(graph.mesh->points[1][0], 10.0f, 1e-5);
  EXPECT_NEAR(graph.mesh->points[1][1], 3.0f, 1e-5);
}

}  // namespace
}  // namespace hydra_multi
