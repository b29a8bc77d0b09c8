#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/decode_error.h"
#include "hydra_multi/dsg/io/json_format.h"
#include "support/random_graphs.h"

namespace hydra_multi::io {
namespace {

// Every attribute survives the binary format exactly (operator== compares all of them).
TEST(BinaryFormat, SceneGraphRoundTripIsExact) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 10; ++trial) {
    const SceneGraph graph = testing::makeRandomGraph(rng);
    const auto decoded = decodeSceneGraphBinary(encodeSceneGraphBinary(graph));
    ASSERT_TRUE(decoded.ok()) << decoded.error();
    EXPECT_EQ(decoded.value(), graph);
  }
  const auto empty = decodeSceneGraphBinary(encodeSceneGraphBinary(SceneGraph()));
  ASSERT_TRUE(empty.ok()) << empty.error();
  EXPECT_EQ(empty.value(), SceneGraph());
}

TEST(BinaryFormat, RobotUpdateRoundTripIsExact) {
  std::mt19937 rng(22);
  for (int trial = 0; trial < 10; ++trial) {
    const RobotUpdate update = testing::makeRandomUpdate(rng, static_cast<uint64_t>(trial));
    const auto decoded = decodeRobotUpdateBinary(encodeRobotUpdateBinary(update));
    ASSERT_TRUE(decoded.ok()) << decoded.error();
    EXPECT_EQ(decoded.value(), update);
  }
}

// An update's bytes split by what it carries add up to its record, and each part grows with its
// own content only: more mesh vertices add to the mesh part, the others stay.
TEST(BinaryFormat, UpdateBytesSplitByCategory) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 10; ++trial) {
    const RobotUpdate update = testing::makeRandomUpdate(rng, static_cast<uint64_t>(trial));
    const RobotUpdateBytes bytes = robotUpdateBytes(update);
    EXPECT_EQ(bytes.total(), encodeRobotUpdateBinary(update).size());
    RobotUpdate more_mesh = update;
    more_mesh.graph.mesh.vertices.push_back(MeshVertex{});
    const RobotUpdateBytes grown = robotUpdateBytes(more_mesh);
    EXPECT_GT(grown.mesh, bytes.mesh);
    EXPECT_EQ(grown.nodes_edges, bytes.nodes_edges);
    EXPECT_EQ(grown.pose_graph, bytes.pose_graph);
    EXPECT_EQ(grown.deformation, bytes.deformation);
    EXPECT_EQ(grown.descriptors, bytes.descriptors);
    RobotUpdate more_poses = update;
    more_poses.pose_graph.push_back(PoseGraphEdge{});
    const RobotUpdateBytes posed = robotUpdateBytes(more_poses);
    EXPECT_EQ(posed.pose_graph, bytes.pose_graph + 8 + 8 + 1 + 12 * 8 + 36 * 8);
    EXPECT_EQ(posed.mesh, bytes.mesh);
  }
}

// A record's size is known without making it, on either side of each varint length boundary.
TEST(BinaryFormat, RecordSizeWithoutTheRecord) {
  for (const size_t n : {0, 1, 127, 128, 300, 16383, 16384, 70000, 2097152}) {
    EXPECT_EQ(recordSize(n), encodeRecord(RecordKind::kRobotUpdate, std::string(n, 'x')).size())
        << n;
  }
}

// A stream is records back to back; the reader hands them out one at a time.
TEST(BinaryFormat, StreamOfRecords) {
  std::mt19937 rng(23);
  std::string stream;
  std::vector<RobotUpdate> updates;
  for (uint64_t i = 0; i < 5; ++i) {
    updates.push_back(testing::makeRandomUpdate(rng, i));
    stream += encodeRobotUpdateBinary(updates.back());
  }
  RecordReader reader(stream);
  for (const RobotUpdate& expected : updates) {
    auto record = reader.next();
    ASSERT_TRUE(record.ok() && record.value().has_value());
    auto update = decodeRobotUpdatePayload(*record.value());
    ASSERT_TRUE(update.ok()) << update.error();
    EXPECT_EQ(update.value(), expected);
  }
  auto end = reader.next();
  ASSERT_TRUE(end.ok());
  EXPECT_FALSE(end.value().has_value());
  // A single-record decoder refuses a stream.
  EXPECT_FALSE(decodeRobotUpdateBinary(stream).ok());
}

// After a damaged record the reader finds the next one: a flipped byte in the middle record costs
// that record only; a cut-off end costs the last one; and without resynchronize() it stops.
TEST(BinaryFormat, ReaderResynchronizesAfterADamagedRecord) {
  std::mt19937 rng(24);
  std::vector<RobotUpdate> updates;
  std::vector<size_t> starts;
  std::string stream;
  for (uint64_t i = 0; i < 5; ++i) {
    updates.push_back(testing::makeRandomUpdate(rng, i));
    starts.push_back(stream.size());
    stream += encodeRobotUpdateBinary(updates.back());
  }
  const auto readAll = [](std::string_view bytes, bool resync) {
    std::vector<uint64_t> sequences;
    std::vector<std::string> errors;
    RecordReader reader(bytes);
    while (true) {
      auto record = reader.next();
      if (!record) {
        errors.push_back(record.error());
        if (resync && reader.resynchronize()) continue;
        break;
      }
      if (!record.value()) break;
      auto update = decodeRobotUpdatePayload(*record.value());
      if (update) sequences.push_back(update.value().sequence);
    }
    return std::make_pair(sequences, errors);
  };
  std::string flipped = stream;
  flipped[(starts[2] + starts[3]) / 2] ^= 0x5A;
  const auto [kept, errors] = readAll(flipped, true);
  EXPECT_EQ(kept, (std::vector<uint64_t>{0, 1, 3, 4}));
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("record at byte " + std::to_string(starts[2])), std::string::npos)
      << errors[0];
  EXPECT_NE(errors[0].find("checksum mismatch"), std::string::npos) << errors[0];
  const auto [strict, strict_errors] = readAll(flipped, false);
  EXPECT_EQ(strict, (std::vector<uint64_t>{0, 1}));
  EXPECT_EQ(strict_errors.size(), 1u);

  const std::string cut = stream.substr(0, starts[4] + 20);
  const auto [before_cut, cut_errors] = readAll(cut, true);
  EXPECT_EQ(before_cut, (std::vector<uint64_t>{0, 1, 2, 3}));
  ASSERT_EQ(cut_errors.size(), 1u);
  EXPECT_NE(cut_errors[0].find("truncated"), std::string::npos) << cut_errors[0];

  // A record's magic bytes themselves damaged: the reader skips to the next record's.
  std::string no_magic = stream;
  no_magic[starts[1]] = 'X';
  EXPECT_EQ(readAll(no_magic, true).first, (std::vector<uint64_t>{0, 2, 3, 4}));
  // resynchronize() without a broken record does nothing.
  RecordReader fresh(stream);
  EXPECT_FALSE(fresh.resynchronize().has_value());
  ASSERT_TRUE(fresh.next().ok());
}

// On a graph with a mesh, the binary file is at least 5 times smaller than our JSON.
TEST(BinaryFormat, AtLeastFiveTimesSmallerThanJsonWithAMesh) {
  std::mt19937 rng(24);
  const SceneGraph graph = testing::makeRandomGraph(rng, {100, 30, 200, 8, 20000, 40000});
  const size_t binary = encodeSceneGraphBinary(graph).size();
  const size_t json = sceneGraphToJson(graph).size();
  EXPECT_GE(static_cast<double>(json) / static_cast<double>(binary), 5.0)
      << "binary " << binary << " bytes, JSON " << json << " bytes";
}

std::string expectError(const std::string& bytes) {
  const auto decoded = decodeSceneGraphBinary(bytes);
  EXPECT_FALSE(decoded.ok());
  return decoded.error();
}

// Re-computes the checksum of a single-record buffer after it was edited on purpose.
void fixChecksum(std::string& record) {
  const std::string_view body(record.data() + 4, record.size() - 8);
  const uint32_t crc = crc32(body);
  for (int i = 0; i < 4; ++i)
    record[record.size() - 4 + i] = static_cast<char>((crc >> (8 * i)) & 0xFF);
}

// Errors say what was wrong and where.
TEST(BinaryFormat, ErrorsNameWhatAndWhere) {
  std::mt19937 rng(25);
  const SceneGraph graph = testing::makeRandomGraph(rng);
  const std::string good = encodeSceneGraphBinary(graph);

  EXPECT_NE(expectError(good.substr(0, good.size() / 2)).find("truncated"), std::string::npos);
  EXPECT_NE(expectError("").find("empty input"), std::string::npos);
  EXPECT_NE(expectError("PK\x03\x04 not ours").find("magic"), std::string::npos);

  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_NE(expectError(flipped).find("checksum mismatch"), std::string::npos);

  std::string version = good;
  version[5] = 9;  // the version's low byte
  fixChecksum(version);
  EXPECT_NE(expectError(version).find("format version 9 is not supported"), std::string::npos);

  // NaN in the first node's position (the payload starts after magic, kind, version, size).
  SceneGraph one;
  one.addOrUpdateNode(makeNode(NodeId('O', 1), Layer::kObjects, {1, 2, 3}));
  std::string nan = encodeSceneGraphBinary(one);
  const size_t payload = 4 + 1 + 2 + 1;
  const size_t position_x = payload + 1 /*node count*/ + 8 /*id*/ + 1 /*layer*/;
  const double not_a_number = std::nan("");
  std::memcpy(&nan[position_x], &not_a_number, sizeof not_a_number);
  fixChecksum(nan);
  const std::string nan_error = expectError(nan);
  EXPECT_NE(nan_error.find("O(1)"), std::string::npos) << nan_error;
  EXPECT_NE(nan_error.find("not finite"), std::string::npos) << nan_error;

  // An edge whose endpoint is not in the file.
  SceneGraph dangling = one;
  dangling.addOrUpdateNode(makeNode(NodeId('p', 1), Layer::kPlaces));
  dangling.addOrUpdateEdge(NodeId('p', 1), NodeId('O', 1));
  std::string bytes = encodeSceneGraphBinary(dangling);
  // Rename the place's id in the node list only: the edge now dangles.
  const std::string place_id = [] {
    ByteWriter w;
    w.u64(NodeId('p', 1).value());
    return w.release();
  }();
  bytes.replace(bytes.find(place_id), 8, [] {
    ByteWriter w;
    w.u64(NodeId('p', 2).value());
    return w.release();
  }());
  fixChecksum(bytes);
  const std::string dangling_error = expectError(bytes);
  EXPECT_NE(dangling_error.find("does not exist"), std::string::npos) << dangling_error;
}

TEST(ByteCodec, VarintsAndZigzagRoundTrip) {
  ByteWriter w;
  const std::vector<uint64_t> unsigned_values = {0, 1, 127, 128, 300, UINT32_MAX, UINT64_MAX};
  const std::vector<int64_t> signed_values = {0, -1, 1, -64, 64, INT64_MIN, INT64_MAX};
  for (const uint64_t v : unsigned_values) w.varint(v);
  for (const int64_t v : signed_values) w.svarint(v);
  ByteReader r(w.bytes());
  for (const uint64_t v : unsigned_values) EXPECT_EQ(r.varint("v"), v);
  for (const int64_t v : signed_values) EXPECT_EQ(r.svarint("v"), v);
  EXPECT_TRUE(r.atEnd());
  EXPECT_THROW(r.u8("past the end"), DecodeError);
  // The CRC-32 check value of "123456789".
  EXPECT_EQ(crc32("123456789"), 0xCBF43926u);
}

}  // namespace
}  // namespace hydra_multi::io
