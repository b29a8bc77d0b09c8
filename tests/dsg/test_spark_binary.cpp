#include "hydra_multi/dsg/io/spark_binary.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

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
void expectApartment(const Graph& g) {
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
  EXPECT_EQ(g.layer_keys, keys);
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

}  // namespace
}  // namespace hydra_multi::io::spark
