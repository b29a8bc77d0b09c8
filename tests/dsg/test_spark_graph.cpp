#include "hydra_multi/dsg/io/spark_graph.h"

#include <gtest/gtest.h>

#include <set>

#include <nlohmann/json.hpp>

#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/io/spark_json.h"
#include "support/random_graphs.h"

namespace hydra_multi::io {
namespace {

std::string fixture(const std::string& name) { return testing::dataDir() + "/spark/" + name; }

SceneGraph load(const std::string& path) {
  auto graph = loadSceneGraph(path);
  EXPECT_TRUE(graph) << graph.error();
  return graph ? std::move(graph).value() : SceneGraph();
}

TEST(SparkGraph, ApartmentFromSparkDsgsBinaryIsTheLegacyJsonsGraph) {
  // The same real Hydra graph: the legacy JSON Hydra wrote, and Spark-DSG's binary of it.
  const SceneGraph binary = load(fixture("apartment.sparkdsg"));
  const SceneGraph legacy = load(testing::dataDir() + "/dsg/apartment_dsg.json");
  ASSERT_EQ(binary.numNodes(), 296u);
  ASSERT_EQ(binary.numNodes(), legacy.numNodes());
  ASSERT_EQ(binary.numEdges(), legacy.numEdges());
  for (const auto& [id, node] : legacy.nodes()) {
    const Node* other = binary.findNode(id);
    ASSERT_NE(other, nullptr) << id.str();
    EXPECT_EQ(other->layer(), node.layer()) << id.str();
    EXPECT_LT((other->position - node.position).norm(), 1e-9) << id.str();
    if (const SemanticAttributes* s = node.semantic()) {
      EXPECT_EQ(other->semantic()->label, s->label) << id.str();
      EXPECT_EQ(other->semantic()->name, s->name) << id.str();
      EXPECT_EQ(other->semantic()->bounding_box.has_value(), s->bounding_box.has_value());
      if (s->bounding_box) {  // Spark-DSG keeps dimensions and centre in single precision
        EXPECT_LT((other->semantic()->bounding_box->min - s->bounding_box->min).norm(), 1e-5);
      }
    }
    if (const AgentAttributes* a = node.find<AgentAttributes>()) {
      EXPECT_EQ(other->find<AgentAttributes>()->keyframe_id, a->keyframe_id);
      EXPECT_EQ(other->find<AgentAttributes>()->timestamp_ns, a->timestamp_ns) << id.str();
    }
  }
  for (const auto& [key, info] : legacy.edges())
    EXPECT_TRUE(binary.hasEdge(key.first(), key.second()));
}

TEST(SparkGraph, OurGraphInSparksFormReadsBackTheSame) {
  const SceneGraph graph = load(fixture("apartment_mesh.sparkdsg"));
  ASSERT_EQ(graph.mesh().vertices.size(), 400u);
  ASSERT_EQ(graph.mesh().faces.size(), 722u);
  const spark::Graph exported = sparkFromSceneGraph(graph);
  // Every layer key in use is listed; agents sit in their prefix's partition.
  const std::vector<spark::LayerKey> keys = {{2, 0}, {2, 97}, {3, 0}, {4, 0}, {5, 0}};
  EXPECT_EQ(exported.layer_keys, keys);
  for (const spark::Node& n : exported.nodes) {
    if (n.attributes.type == "AgentNodeAttributes") {
      EXPECT_EQ(n.partition, 97u);
    }
    const nlohmann::json metadata = nlohmann::json::parse(n.attributes.metadata);
    EXPECT_EQ(metadata["id"], NodeId(n.id).str());
  }
  auto decoded = spark::decodeFile(spark::encodeFile(exported));
  ASSERT_TRUE(decoded) << decoded.error();
  auto back = sceneGraphFromSpark(decoded.value());
  ASSERT_TRUE(back) << back.error();
  EXPECT_TRUE(back.value().left_out.empty());
  EXPECT_TRUE(back.value().graph == graph) << "our graph changed through Spark-DSG's layout";
  // Without the mesh, the flag says so.
  EXPECT_FALSE(sparkFromSceneGraph(graph, false).mesh);
}

TEST(SparkGraph, StationIdsStayUniqueAndNameTheirRobot) {
  SceneGraph graph;
  for (uint8_t r = 0; r < 3; ++r) {
    Node object = makeNode(NodeId::station('O', RobotId(r), 0), Layer::kObjects, {1.0 * r, 0, 0});
    ASSERT_TRUE(graph.addOrUpdateNode(object));
  }
  // Each robot's mesh vertices, in runs (Spark's mesh has no robot: the metadata says).
  for (uint8_t r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) {
      MeshVertex v;
      v.position = {float(r), float(k), 0.f};
      v.robot = RobotId(r);
      graph.mesh().vertices.push_back(v);
    }
    graph.mesh().faces.push_back({uint32_t(3 * r), uint32_t(3 * r + 1), uint32_t(3 * r + 2)});
  }
  const spark::Graph exported = sparkFromSceneGraph(graph);
  EXPECT_NE(exported.metadata.find(R"("mesh_robots":[["a",0,3],["b",3,3],["c",6,3]])"),
            std::string::npos)
      << exported.metadata;
  std::set<uint64_t> ids;
  for (const spark::Node& n : exported.nodes) {
    ids.insert(n.id);
    EXPECT_EQ(n.id >> 56, uint64_t('O'));
    const nlohmann::json metadata = nlohmann::json::parse(n.attributes.metadata);
    EXPECT_EQ(metadata["robot"], NodeId(n.id).sourceRobot()->str());
  }
  EXPECT_EQ(ids.size(), 3u);
  auto back = sceneGraphFromSpark(exported);
  ASSERT_TRUE(back) << back.error();
  EXPECT_TRUE(back.value().graph == graph);
}

TEST(SparkGraph, WhatOurGraphHasNoPlaceForIsCountedAndAgentsMustSitInTheirPartition) {
  auto decoded = spark::decodeFile(readFile(fixture("apartment.sparkdsg")).value());
  ASSERT_TRUE(decoded) << decoded.error();
  spark::Graph g = decoded.value();
  // A 2D place (layer 3, partition 1) and an agent in another robot's partition.
  spark::Node place2d = g.nodes.front();
  place2d.layer = 3;
  place2d.partition = 1;
  place2d.id = (uint64_t('Q') << 56) | 1;
  g.nodes.push_back(place2d);
  auto imported = sceneGraphFromSpark(g);
  ASSERT_TRUE(imported) << imported.error();
  EXPECT_EQ(imported.value().graph.numNodes(), 296u);
  ASSERT_EQ(imported.value().left_out.size(), 1u);
  EXPECT_NE(imported.value().left_out.begin()->first.find("layer 3 partition 1"),
            std::string::npos);
  for (spark::Node& n : g.nodes) {
    if (n.attributes.type == "AgentNodeAttributes") {
      n.partition = 98;
      break;
    }
  }
  auto refused = sceneGraphFromSpark(g);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("partition 98"), std::string::npos) << refused.error();
}

}  // namespace
}  // namespace hydra_multi::io

namespace hydra_multi::io {
namespace {

TEST(SparkGraph, CurrentJsonLayoutReadsAsTheBinaryOfTheSameGraph) {
  // Spark-DSG 1.1.3 wrote each graph twice: as JSON (colour {r,g,b,a}, boxes with dimensions,
  // partitions, the agents' stamps in their attributes, the mesh) and as its binary.
  for (const std::string name : {"apartment", "apartment_mesh"}) {
    const SceneGraph json = load(fixture(name + ".json"));
    const SceneGraph binary = load(fixture(name + ".sparkdsg"));
    EXPECT_EQ(json.numNodes(), 296u) << name;
    EXPECT_TRUE(json == binary) << name << ": the JSON and the binary give different graphs";
  }
  EXPECT_EQ(load(fixture("apartment_mesh.json")).mesh().faces.size(), 722u);
}

TEST(SparkGraph, UnsetStampsAboveTwoToTheSixtyThreeAreRead) {
  // Real Hydra files carry an unset last_update_time_ns of 2^64 - 1 (Spark-DSG's uint64).
  const std::string text = R"({"nodes": [{"id": 5692549928996306944, "layer": 5, "partition": 0,
    "attributes": {"type": "SemanticNodeAttributes", "position": [1, 2, 3],
    "last_update_time_ns": 18446744073709551615, "is_active": true, "name": "building",
    "color": {"r": 1, "g": 2, "b": 3, "a": 255}, "semantic_label": 0,
    "bounding_box": {"type": "INVALID", "dimensions": [0, 0, 0], "world_P_center": [0, 0, 0],
    "world_R_center": {"w": 1, "x": 0, "y": 0, "z": 0}}}}], "edges": []})";
  auto graph = sceneGraphFromSparkJson(text);
  ASSERT_TRUE(graph) << graph.error();
  const Node& b = graph.value().nodes().begin()->second;
  EXPECT_EQ(b.last_update_time_ns, 0);
  EXPECT_EQ(b.semantic()->color, (Color{1, 2, 3}));
}

}  // namespace
}  // namespace hydra_multi::io
