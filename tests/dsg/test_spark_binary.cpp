#include "hydra_multi/dsg/io/spark_binary.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "hydra_multi/dsg/io/spark_graph.h"
#include "support/random_graphs.h"

namespace hydra_multi::io::spark {
namespace {

std::string readFixture(const std::string& name) {
  std::ifstream in(testing::dataDir() + "/spark/" + name, std::ios::binary);
  EXPECT_TRUE(in) << name;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// Nodes per (layer, partition).
std::map<std::pair<int64_t, uint32_t>, size_t> perLayer(const Graph& g) {
  std::map<std::pair<int64_t, uint32_t>, size_t> counts;
  for (const Node& n : g.nodes) ++counts[{n.layer, n.partition}];
  return counts;
}

// The counts ../shared/data/spark/README.md gives (from Spark-DSG itself).
// (Before 1.1.2 the layers are listed by id: `with_partitions` false.)
void expectApartment(const Graph& g, bool with_partitions = true) {
  EXPECT_EQ(g.nodes.size(), 296u);
  EXPECT_EQ(g.edges.size(), 742u);
  const std::map<std::pair<int64_t, uint32_t>, size_t> expected = {
      {{2, 0}, 7}, {{2, 97}, 102}, {{3, 0}, 185}, {{4, 0}, 1}, {{5, 0}, 1}};
  EXPECT_EQ(perLayer(g), expected);
  std::map<std::string, size_t> types;
  for (const Node& n : g.nodes) ++types[n.attributes.type];
  const std::map<std::string, size_t> expected_types = {{"AgentNodeAttributes", 102},
                                                        {"ObjectNodeAttributes", 7},
                                                        {"PlaceNodeAttributes", 185},
                                                        {"RoomNodeAttributes", 1},
                                                        {"SemanticNodeAttributes", 1}};
  EXPECT_EQ(types, expected_types);
  const std::vector<LayerKey> keys = {{2, 0}, {2, 97}, {3, 0}, {4, 0}, {5, 0}};
  const std::vector<LayerKey> ids = {{2, 0}, {3, 0}, {4, 0}, {5, 0}};
  EXPECT_EQ(g.layer_keys, with_partitions ? keys : ids);
  // Agents carry their true stamps (3.65 s to about 28 s) and Hydra's external key.
  for (const Node& n : g.nodes) {
    if (n.attributes.type != "AgentNodeAttributes") continue;
    EXPECT_EQ(n.id >> 56, uint64_t('a'));
    EXPECT_GE(n.attributes.timestamp_ns, 3'600'000'000);
    EXPECT_LE(n.attributes.timestamp_ns, 29'000'000'000);
  }
}

TEST(SparkBinary, ApartmentFileDecodesToSparkDsgsCountsAndEncodesToTheSameBytes) {
  const std::string bytes = readFixture("apartment.sparkdsg");
  FileHeader header;
  auto graph = decodeFile(bytes, &header);
  ASSERT_TRUE(graph) << graph.error();
  EXPECT_EQ(header.project, "main");
  EXPECT_EQ(header.version, kVersion);
  expectApartment(graph.value());
  EXPECT_FALSE(graph.value().mesh);
  EXPECT_TRUE(encodeFile(graph.value(), header) == bytes) << "the file written back differs";
}

TEST(SparkBinary, ApartmentWireMessageIsTheFileWithoutItsHeader) {
  const std::string wire = readFixture("apartment.zmq.bin");
  auto graph = decodeWire(wire);
  ASSERT_TRUE(graph) << graph.error();
  expectApartment(graph.value());
  EXPECT_TRUE(encodeWire(graph.value()) == wire) << "the message written back differs";
  EXPECT_EQ(readFixture("apartment.sparkdsg").substr(29), wire);
}

TEST(SparkBinary, MeshFixtureHasItsGridAndEncodesToTheSameBytes) {
  for (const std::string name : {"apartment_mesh.sparkdsg", "apartment_mesh.zmq.bin"}) {
    const std::string bytes = readFixture(name);
    const bool file = name.find(".sparkdsg") != std::string::npos;
    auto graph = file ? decodeFile(bytes) : decodeWire(bytes);
    ASSERT_TRUE(graph) << name << ": " << graph.error();
    expectApartment(graph.value());
    ASSERT_TRUE(graph.value().mesh) << name;
    const Mesh& m = *graph.value().mesh;
    EXPECT_EQ(m.points.size(), 400u);
    EXPECT_EQ(m.faces.size(), 722u);
    EXPECT_TRUE(m.has_colors && m.has_stamps && m.has_labels && m.has_first_seen);
    ASSERT_EQ(m.colors.size(), 400u);
    // Vertex k = j*20 + i: colour (i*255/19, j*255/19, 7k mod 256, 255), stamp 1e9 + k*1e6.
    const size_t k = 3 * 20 + 5;
    EXPECT_EQ(m.colors[k][0], 5 * 255 / 19);
    EXPECT_EQ(m.colors[k][1], 3 * 255 / 19);
    EXPECT_EQ(m.colors[k][2], (7 * k) % 256);
    EXPECT_EQ(m.stamps[k], 1'000'000'000u + k * 1'000'000u);
    EXPECT_EQ(m.labels[k], 5 / 5 + 10 * (3 / 5));
    const std::string again = file ? encodeFile(graph.value()) : encodeWire(graph.value());
    EXPECT_TRUE(again == bytes) << name << ": written back differs";
  }
}

TEST(SparkBinary, CutOrDamagedBuffersAreErrorsNamingTheByte) {
  const std::string wire = readFixture("apartment_mesh.zmq.bin");
  // Cut anywhere: an error, never a crash (and a cut after the edges is a graph without a mesh,
  // as Spark-DSG reads it).
  size_t errors = 0;
  for (size_t cut = 0; cut < wire.size(); cut += 2999) {
    auto graph = decodeWire(std::string_view(wire).substr(0, cut));
    if (!graph) {
      ++errors;
      EXPECT_NE(graph.error().find("byte "), std::string::npos) << graph.error();
    }
  }
  EXPECT_GT(errors, wire.size() / 2999 - 2);
  // A tag changed: the field is named. The first node's layer tag (d3) follows the node header.
  std::string bad = wire;
  const size_t node = bad.find(std::string("\x00\xdd\x04\x00\x00\x00\xd3", 7));
  ASSERT_NE(node, std::string::npos);
  bad[node + 6] = static_cast<char>(0xce);
  auto refused = decodeWire(bad);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("node 0"), std::string::npos) << refused.error();
  EXPECT_NE(refused.error().find("node layer: expected INT64 (d3), found UINT32 (ce)"),
            std::string::npos)
      << refused.error();
  // A NaN where a number must be: refused by name (the first node's position follows its
  // metadata "{}").
  std::string nan = wire;
  const size_t position = nan.find("\x7b\x7d\xcb", node);
  ASSERT_NE(position, std::string::npos);
  const double not_a_number = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(nan.data() + position + 3, &not_a_number, 8);
  refused = decodeWire(nan);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("position: not a finite number"), std::string::npos)
      << refused.error();
  // A huge count cannot make the decoder allocate: it is checked against the bytes left.
  std::string huge = wire;
  huge[1] = huge[2] = huge[3] = huge[4] = static_cast<char>(0x7f);
  refused = decodeWire(huge);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("layer keys"), std::string::npos) << refused.error();
  // Trailing bytes, another version, not a file.
  EXPECT_FALSE(decodeWire(wire + "x"));
  EXPECT_FALSE(decodeWire(wire, Version{1, 1, 2}));
  auto not_file = decodeFile(wire);
  ASSERT_FALSE(not_file);
  EXPECT_NE(not_file.error().find("file header"), std::string::npos) << not_file.error();
}

TEST(SparkBinary, UnknownAttributeTypeIsRefusedByName) {
  auto graph = decodeWire(readFixture("apartment.zmq.bin"));
  ASSERT_TRUE(graph) << graph.error();
  Graph g = graph.value();
  // Point the building at a type of the names table this codec does not read.
  const auto khronos =
      std::find(g.node_types.begin(), g.node_types.end(), "KhronosObjectAttributes");
  ASSERT_NE(khronos, g.node_types.end());
  const std::string bytes = encodeWire(g);
  const auto found = std::find_if(g.nodes.begin(), g.nodes.end(), [](const Node& n) {
    return n.attributes.type == "SemanticNodeAttributes";
  });
  ASSERT_NE(found, g.nodes.end());
  const Node& building = *found;
  std::string wire = bytes;
  // Re-encode with the type id changed in place: find the building's record by its id.
  const uint64_t id = building.id;
  std::string key(8, '\0');
  std::memcpy(key.data(), &id, 8);
  const size_t at = wire.find("\xcf" + key);
  ASSERT_NE(at, std::string::npos);
  const size_t type = at + 9 + 5;  // after the id: partition (ce + 4), then cc and the type id
  ASSERT_EQ(static_cast<uint8_t>(wire[type]), 0xcc);
  wire[type + 1] = static_cast<char>(khronos - g.node_types.begin());
  auto refused = decodeWire(wire);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("'KhronosObjectAttributes' is not a type this codec reads"),
            std::string::npos)
      << refused.error();
}

// Every version this codec knows, as Spark-DSG's readers gate them.
const std::vector<Version> kVersions = {{1, 0, 2}, {1, 0, 3}, {1, 0, 4}, {1, 0, 5}, {1, 0, 6},
                                        {1, 1, 0}, {1, 1, 1}, {1, 1, 2}, {1, 1, 3}, {1, 1, 4}};

// Two scene graphs equal but for boxes within float rounding (before 1.0.3 a box goes as its min
// and max).
void expectSameGraph(const SceneGraph& a, const SceneGraph& b, const std::string& what) {
  ASSERT_EQ(a.numNodes(), b.numNodes()) << what;
  for (const auto& [id, node] : a.nodes()) {
    const hydra_multi::Node* other = b.findNode(id);
    ASSERT_NE(other, nullptr) << what << ": " << id.str();
    hydra_multi::Node x = node, y = *other;
    if (x.semantic() && y.semantic() && x.semantic()->bounding_box && y.semantic()->bounding_box) {
      EXPECT_LT((x.semantic()->bounding_box->min - y.semantic()->bounding_box->min).norm(), 1e-5)
          << what << ": " << id.str();
      EXPECT_LT((x.semantic()->bounding_box->max - y.semantic()->bounding_box->max).norm(), 1e-5)
          << what << ": " << id.str();
      x.semantic()->bounding_box.reset();
      y.semantic()->bounding_box.reset();
    }
    EXPECT_EQ(x, y) << what << ": " << id.str();
  }
  EXPECT_EQ(a.edges(), b.edges()) << what;
  EXPECT_EQ(a.mesh(), b.mesh()) << what;
}

TEST(SparkBinary, EveryVersionFrom102To114WritesWhatItReadsAndCarriesTheSameGraph) {
  const Graph fixture = decodeWire(readFixture("apartment_mesh.zmq.bin")).value();
  const SceneGraph ours = sceneGraphFromSpark(fixture).value().graph;
  for (const Version& v : kVersions) {
    const std::string bytes = encodeWire(fixture, v);
    auto decoded = decodeWire(bytes, v);
    ASSERT_TRUE(decoded) << v.str() << ": " << decoded.error();
    EXPECT_TRUE(encodeWire(decoded.value(), v) == bytes) << v.str() << ": written back differs";
    expectApartment(decoded.value(), Version{1, 1, 2} <= v);
    auto imported = sceneGraphFromSpark(decoded.value());
    ASSERT_TRUE(imported) << v.str() << ": " << imported.error();
    expectSameGraph(imported.value().graph, ours, v.str());
    // As a file, the header names the version.
    FileHeader header;
    header.version = v;
    FileHeader read;
    ASSERT_TRUE(decodeFile(encodeFile(fixture, header), &read)) << v.str();
    EXPECT_EQ(read.version, v);
  }
  // 1.1.3, the version the fixture was written in, gives its bytes back.
  EXPECT_TRUE(encodeWire(fixture, kVersion) == readFixture("apartment_mesh.zmq.bin"));
}

// The test vector of spark-dsg-wire.md §1.12 (one object, 1.1.3) and the same graph laid out by
// the rules of §1.10 for 1.0.2, byte by byte.
TEST(SparkBinary, OneNodeGraphInTheLayoutsOf113And102) {
  Graph g;
  g.layer_keys = {{2, 0}};
  g.node_types = {"NodeAttributes"};
  g.edge_types = {"EdgeAttributes"};
  g.layer_names = {{"OBJECTS", {2, 0}}};
  Node n;
  n.layer = 2;
  n.id = 0x4F00000000000005;
  n.attributes.type = "NodeAttributes";
  n.attributes.position = {1, 2, 3};
  g.nodes.push_back(n);
  const auto hex = [](const std::string& text) {
    std::string bytes;
    for (size_t i = 0; i < text.size();) {
      if (text[i] == ' ') {
        ++i;
        continue;
      }
      bytes.push_back(static_cast<char>(std::stoi(text.substr(i, 2), nullptr, 16)));
      i += 2;
    }
    return bytes;
  };
  const std::string names =
      "dd01000000 dd0e000000 4e6f646541747472696275746573 "   // NodeAttributes
      "dd01000000 dd0e000000 4564676541747472696275746573 ";  // EdgeAttributes
  const std::string position =
      "cb000000000000f03f cb0000000000000040 cb0000000000000840 cf0000000000000000 c2 ";
  const std::string v113 =
      hex("dd01000000 dd02000000 d30200000000000000 ce00000000 " + names +
          "dd01000000 dd07000000 4f424a45435453 dd02000000 d30200000000000000 ce00000000 "
          "dd02000000 7b7d "
          "00 dd04000000 d30200000000000000 cf050000000000004f ce00000000 cc00 dd020000007b7d " +
          position + "c2 01 00 01 c2");
  EXPECT_EQ(v113.size(), 195u);
  EXPECT_TRUE(encodeWire(g, kVersion) == v113);
  // 1.0.2: layer ids (unsigned, as the node's layer), no layer names, no metadata, the node's
  // stamp (none: c0) for its partition, no is_predicted, and the (empty) array of dynamic nodes.
  const std::string v102 = hex("dd01000000 cf0200000000000000 " + names +
                               "00 dd04000000 cf0200000000000000 cf050000000000004f c0 cc00 " +
                               position + "01 00 01 00 01 c2");
  EXPECT_TRUE(encodeWire(g, Version{1, 0, 2}) == v102);
  auto back = decodeWire(v102, Version{1, 0, 2});
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(back.value().nodes.size(), 1u);
  EXPECT_EQ(back.value().nodes[0].attributes.position, n.attributes.position);
}

TEST(SparkBinary, BeforeVersion110AgentsAreDynamicNodesStampedWithTheirTime) {
  const Graph fixture = decodeWire(readFixture("apartment.zmq.bin")).value();
  const std::string bytes = encodeWire(fixture, Version{1, 0, 6});
  const Graph old = decodeWire(bytes, Version{1, 0, 6}).value();
  size_t agents = 0;
  for (size_t i = 0; i < old.nodes.size(); ++i) {
    const Node& n = old.nodes[i];
    if (n.attributes.type != "AgentNodeAttributes") {
      EXPECT_FALSE(n.stamp_ns);
      EXPECT_EQ(n.partition, 0u);
      EXPECT_EQ(agents, 0u) << "the agents come last, in their own array";
      continue;
    }
    ++agents;
    ASSERT_TRUE(n.stamp_ns);
    EXPECT_EQ(n.partition, uint32_t('a'));
    EXPECT_EQ(*n.stamp_ns, n.attributes.timestamp_ns);
    EXPECT_GE(n.attributes.timestamp_ns, 3'600'000'000);
  }
  EXPECT_EQ(agents, 102u);
}

TEST(SparkBinary, TwoDimensionalPlacesInTheLayoutsOf113And114) {
  Graph g;
  g.layer_keys = {{3, 1}};
  g.node_types = knownNodeTypes();
  g.edge_types = {"EdgeAttributes"};
  Node n;
  n.layer = 3;
  n.partition = 1;
  n.id = 0x5100000000000002;
  n.type_id = static_cast<uint8_t>(
      std::find(g.node_types.begin(), g.node_types.end(), "Place2dNodeAttributes") -
      g.node_types.begin());
  Attributes& a = n.attributes;
  a.type = "Place2dNodeAttributes";
  a.semantic_feature = {0, 0, 0xca, {}};
  a.bounding_box.rotation = {3, 3, 0xca, {1, 0, 0, 0, 1, 0, 0, 0, 1}};
  a.boundary = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  a.ellipse_centroid = {0.5, 0.5, 0};
  a.ellipse_matrix_compress = {2, 2, 0xcb, {1, 0, 0, 1}};
  a.ellipse_matrix_expand = {2, 2, 0xcb, {1, 0, 0, 1}};
  a.pcl_boundary_connections = {4, 5};
  a.pcl_mesh_connections = {7, 8, 9};
  a.has_active_mesh_indices = true;
  a.min_mesh_index = 7;
  a.max_mesh_index = 9;
  a.need_finish_merge = true;
  g.nodes.push_back(n);
  const std::string v114 = encodeWire(g, Version{1, 1, 4});
  const Attributes back = decodeWire(v114, Version{1, 1, 4}).value().nodes.at(0).attributes;
  EXPECT_EQ(back.pcl_mesh_connections, a.pcl_mesh_connections);
  EXPECT_EQ(back.pcl_boundary_connections, a.pcl_boundary_connections);
  EXPECT_EQ(back.boundary, a.boundary);
  EXPECT_EQ(back.min_mesh_index, 7u);
  EXPECT_EQ(back.max_mesh_index, 9u);
  EXPECT_TRUE(back.need_finish_merge);
  // 1.1.4's fields follow the semantic ones with the mesh connections: cf 07, cf 08, cf 09 come
  // before the boundary's first double.
  const size_t mesh = v114.find(std::string("\xdd\x03\x00\x00\x00\xcf\x07", 7));
  const size_t boundary = v114.find(std::string("\xdd\x03\x00\x00\x00\xcb", 6));
  ASSERT_NE(mesh, std::string::npos);
  ASSERT_NE(boundary, std::string::npos);
  EXPECT_LT(mesh, boundary);
  // 1.1.3 has no place for the index range: it reads back without it, the rest the same.
  const Attributes old =
      decodeWire(encodeWire(g, kVersion), kVersion).value().nodes.at(0).attributes;
  EXPECT_EQ(old.pcl_mesh_connections, a.pcl_mesh_connections);
  EXPECT_EQ(old.boundary, a.boundary);
  EXPECT_EQ(old.min_mesh_index, 0u);
  EXPECT_FALSE(old.need_finish_merge);
  // Read in the other's layout, each fails (a bool where a count is due, or the reverse).
  EXPECT_FALSE(decodeWire(v114, kVersion));
}

TEST(SparkBinary, VersionsOutsideThoseItKnowsAreRefusedByName) {
  const std::string wire = readFixture("apartment.zmq.bin");
  auto old = decodeWire(wire, Version{1, 0, 1});
  ASSERT_FALSE(old);
  EXPECT_EQ(old.error(),
            "spark binary (wire): format 1.0.1 is older than 1.0.2, the oldest Spark-DSG reads");
  auto newer = decodeWire(wire, Version{1, 2, 0});
  ASSERT_FALSE(newer);
  EXPECT_EQ(newer.error(),
            "spark binary (wire): format 1.2.0 is newer than 1.1.4, the newest this codec knows");
  FileHeader header;
  header.version = {1, 0, 1};
  std::string file = encodeFileHeader(header) + wire;
  auto refused = decodeFile(file);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("format 1.0.1 is older"), std::string::npos) << refused.error();
  EXPECT_THROW(encodeWire(Graph{}, Version{1, 2, 0}), std::invalid_argument);
  EXPECT_EQ(Version::parse("1.0.6").value(), (Version{1, 0, 6}));
  EXPECT_FALSE(Version::parse("1.0"));
  EXPECT_FALSE(Version::parse("1.0.6x"));
  EXPECT_FALSE(Version::parse("01.0.6"));
  EXPECT_FALSE(Version::parse("1.0.256"));
}

}  // namespace
}  // namespace hydra_multi::io::spark
