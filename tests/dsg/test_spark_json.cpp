#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/io/json_fields.h"
#include "hydra_multi/dsg/io/json_format.h"
#include "hydra_multi/dsg/io/spark_json.h"
#include "support/random_graphs.h"

namespace hydra_multi::io {
namespace {

SceneGraph loadApartment() {
  const std::string path = testing::dataDir() + "/dsg/apartment_dsg.json";
  auto graph = loadSceneGraph(path);
  if (!graph) ADD_FAILURE() << graph.error();
  return graph ? std::move(graph).value() : SceneGraph();
}

// What the importer leaves out of the real Hydra file is said, key by key (the bag of words,
// the deformation and voxblox links, the boxes of places, which are invalid there); our own JSON
// of the same graph is read whole.
TEST(SparkJson, SaysWhatItDidNotRead) {
  const std::string path = testing::dataDir() + "/dsg/apartment_dsg.json";
  std::map<std::string, size_t> unread;
  ASSERT_TRUE(loadSceneGraph(path, &unread).ok());
  EXPECT_EQ(unread.size(), 19u);
  EXPECT_EQ(describeUnread(path, unread),
            path +
                ": 19 keys not read: directed, edges[].info.type (742 times), layer_ids, "
                "mesh_edges, mesh_layer_id, multigraph, nodes[].attributes.bounding_box.max "
                "(187 times), nodes[].attributes.bounding_box.min (187 times), ...");
  auto root = parseJson(readFile(path).value(), "Spark-DSG JSON");
  ASSERT_TRUE(root.ok());
  KeyUse use;
  ASSERT_TRUE(sceneGraphFromSparkJsonValue(root.value()).ok());
  const auto keys = use.unread(root.value());
  EXPECT_EQ(keys.at("nodes[].attributes.dbow_ids"), 102u);
  EXPECT_EQ(keys.at("nodes[].attributes.deformation_connections"), 185u);
  EXPECT_EQ(keys.count("nodes[].attributes.position"), 0u);
  EXPECT_EQ(keys.count("nodes[].attributes.semantic_label"), 0u);

  const std::string ours = ::testing::TempDir() + "apartment_ours.json";
  ASSERT_TRUE(saveSceneGraph(ours, loadApartment()).ok());
  std::map<std::string, size_t> ours_unread = {{"unset", 1}};
  ASSERT_TRUE(loadSceneGraph(ours, &ours_unread).ok());
  EXPECT_TRUE(ours_unread.empty());  // nothing to say
}

// The real Hydra output loads with the counts of data/README.md.
TEST(SparkJson, ReadsTheRealApartmentGraph) {
  const SceneGraph g = loadApartment();
  EXPECT_EQ(g.numNodes(), 296u);
  EXPECT_EQ(g.numEdges(), 742u);
  EXPECT_EQ(g.numNodes(Layer::kAgents), 102u);
  EXPECT_EQ(g.numNodes(Layer::kObjects), 7u);
  EXPECT_EQ(g.numNodes(Layer::kPlaces), 185u);
  EXPECT_EQ(g.numNodes(Layer::kRooms), 1u);
  EXPECT_EQ(g.numNodes(Layer::kBuildings), 1u);
  EXPECT_EQ(g.robots(), std::vector<RobotId>{RobotId(0)});
}

// Attribute values as they stand in the file (checked by hand against apartment_dsg.json).
TEST(SparkJson, ReadsAttributeValues) {
  const SceneGraph g = loadApartment();
  const Node& object = g.getNode(NodeId('O', 0));
  const auto& o = *object.find<ObjectAttributes>();
  EXPECT_EQ(o.semantic.label, 5u);  // chair in the uHumans2 apartment label space
  EXPECT_EQ(o.semantic.name, "O(0)");
  EXPECT_EQ(o.semantic.color, (Color{219, 128, 223}));
  ASSERT_TRUE(o.semantic.bounding_box.has_value());
  EXPECT_DOUBLE_EQ(o.semantic.bounding_box->min.x(), -13.72044849395752);
  EXPECT_DOUBLE_EQ(o.semantic.bounding_box->max.z(), 1.9747127294540405);
  EXPECT_EQ(o.mesh_vertices.front(), 602u);
  EXPECT_DOUBLE_EQ(object.position.x(), -13.216781616210938);
  EXPECT_EQ(object.last_update_time_ns, 112);

  const Node& place = g.getNode(NodeId(8070450532247928838ULL));
  EXPECT_DOUBLE_EQ(place.find<PlaceAttributes>()->distance, 0.800000011920929);
  EXPECT_FALSE(place.find<PlaceAttributes>()->semantic.bounding_box.has_value());
  EXPECT_EQ(g.findEdge(NodeId(8070450532247928838ULL), NodeId(8070450532247928850ULL))->weight,
            0.7280110120773315);
  EXPECT_TRUE(g.findEdge(NodeId(8070450532247928838ULL), NodeId(8070450532247928850ULL))->weighted);

  const Node& agent = g.getNode(NodeId('a', 0));
  const auto& a = *agent.find<AgentAttributes>();
  EXPECT_DOUBLE_EQ(a.orientation.w(), 0.998922027020804);
  EXPECT_DOUBLE_EQ(a.orientation.z(), -0.04641965028571606);
  EXPECT_EQ(a.timestamp_ns, 3647910000);
  EXPECT_EQ(a.keyframe_id, NodeId('a', 0).value());
  EXPECT_EQ(g.parent(NodeId('a', 0)).value().category(), 'p');

  const Node& room = g.getNode(NodeId('R', 0));
  EXPECT_EQ(room.find<RoomAttributes>()->semantic.name, "R(0)");
  EXPECT_EQ(g.parent(NodeId('R', 0)), NodeId('B', 0));
  EXPECT_EQ(g.getNode(NodeId('B', 0)).find<BuildingAttributes>()->semantic.label, 22u);
}

// apartment -> .dsgb -> .json -> back gives the same graph, attribute for attribute.
TEST(SparkJson, ApartmentThroughBinaryAndJsonIsExact) {
  const SceneGraph g = loadApartment();
  auto from_binary = decodeSceneGraphBinary(encodeSceneGraphBinary(g));
  ASSERT_TRUE(from_binary.ok()) << from_binary.error();
  auto from_json = sceneGraphFromJson(sceneGraphToJson(from_binary.value()));
  ASSERT_TRUE(from_json.ok()) << from_json.error();
  EXPECT_EQ(from_json.value(), g);
}

// Our Spark-DSG export reads back with every attribute the layout holds (all but the mesh),
// for the real graph and for random graphs with station ids.
TEST(SparkJson, ExportReadsBackExactly) {
  auto apartment = sceneGraphFromSparkJson(sceneGraphToSparkJson(loadApartment()));
  ASSERT_TRUE(apartment.ok()) << apartment.error();
  EXPECT_EQ(apartment.value(), loadApartment());

  std::mt19937 rng(41);
  for (int trial = 0; trial < 5; ++trial) {
    SceneGraph g = testing::makeRandomGraph(rng);
    g.mesh() = Mesh();  // not part of the layout
    g.addOrUpdateNode(makeNode(NodeId::station('O', RobotId(2), 5), Layer::kObjects, {1, 1, 1}));
    auto back = sceneGraphFromSparkJson(sceneGraphToSparkJson(g));
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_EQ(back.value(), g);
  }
}

TEST(SparkJson, ErrorsNameTheNode) {
  const auto layer = sceneGraphFromSparkJson(
      R"J({"nodes": [{"id": 5, "layer": 20, "attributes": {"position": [0, 0, 0]}}], "edges": []})J");
  ASSERT_FALSE(layer.ok());
  EXPECT_NE(layer.error().find("nodes[0]: node #0(5): layer 20 is not supported"),
            std::string::npos)
      << layer.error();
  const auto box = sceneGraphFromSparkJson(
      R"J({"nodes": [{"id": 5, "layer": 2, "attributes": {"position": [0, 0, 0],
          "bounding_box": {"type": "OBB"}}}], "edges": []})J");
  ASSERT_FALSE(box.ok());
  EXPECT_NE(box.error().find("bounding box of type OBB without dimensions"), std::string::npos)
      << box.error();
  const auto kind = sceneGraphFromSparkJson(
      R"J({"nodes": [{"id": 5, "layer": 2, "attributes": {"position": [0, 0, 0],
          "bounding_box": {"type": "SPHERE"}}}], "edges": []})J");
  ASSERT_FALSE(kind.ok());
  EXPECT_NE(kind.error().find("bounding box type 'SPHERE' is not supported"), std::string::npos)
      << kind.error();
}

// A .json file is read as ours or as Spark-DSG's by its content.
TEST(GraphFile, DetectsJsonLayoutAndWritesByExtension) {
  std::mt19937 rng(42);
  SceneGraph g = testing::makeRandomGraph(rng, {4, 2, 5, 1, 0, 0});
  const std::string dir = ::testing::TempDir();
  for (const std::string name : {"g.json", "g.spark.json", "g.dsgb"}) {
    ASSERT_TRUE(saveSceneGraph(dir + name, g).ok());
    auto back = loadSceneGraph(dir + name);
    ASSERT_TRUE(back.ok()) << back.error();
    EXPECT_EQ(back.value(), g) << name;
  }
  ASSERT_TRUE(writeFile(dir + "spark_as.json", sceneGraphToSparkJson(g)).ok());
  auto spark = loadSceneGraph(dir + "spark_as.json");
  ASSERT_TRUE(spark.ok()) << spark.error();
  EXPECT_EQ(spark.value(), g);
  EXPECT_FALSE(loadSceneGraph(dir + "missing.json").ok());
  EXPECT_NE(loadSceneGraph(dir + "g.txt").error().find("unknown extension"), std::string::npos);
}

}  // namespace
}  // namespace hydra_multi::io
