// Decoding never crashes: thousands of seeded mutations of valid inputs, in every format, are each
// either decoded into a valid graph or update, or rejected with a message. Run under ASan/UBSan by
// `make test-sanitize`.

#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/json_fields.h"
#include "hydra_multi/dsg/io/json_format.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/io/spark_graph.h"
#include "hydra_multi/dsg/io/spark_json.h"
#include "support/mutations.h"
#include "support/random_graphs.h"

namespace hydra_multi::io {
namespace {

using Decoder = std::function<Status(const std::string&)>;

struct Tally {
  int decoded = 0;
  int rejected = 0;
};

// Runs the decoder; it must return (no crash, no escaping exception) with a usable outcome.
void check(const Decoder& decode, const std::string& input, Tally& tally) {
  Status status;
  ASSERT_NO_THROW(status = decode(input));
  if (status.ok()) {
    ++tally.decoded;
  } else {
    ++tally.rejected;
    ASSERT_FALSE(status.message().empty());
  }
}

// A record with a valid frame and checksum around any payload, so mutations reach the decoder.
std::string frame(RecordKind kind, const std::string& payload) {
  return encodeRecord(kind, payload);
}

std::string payloadOf(const std::string& record) {
  RecordReader reader(record);
  auto view = reader.next();
  return std::string(view.value()->payload);
}

// Structure-aware JSON mutations: replace a random value by one of the wrong type or range, or
// delete a member.
void mutateJsonTree(Json& j, std::mt19937& rng, int depth = 0) {
  const bool descend = (j.is_object() || j.is_array()) && !j.empty() && depth < 8 && rng() % 4 != 0;
  if (descend) {
    const size_t i = rng() % j.size();
    if (j.is_object() && rng() % 6 == 0) {
      j.erase(std::next(j.begin(), static_cast<std::ptrdiff_t>(i)).key());
      return;
    }
    mutateJsonTree(
        j.is_object() ? std::next(j.begin(), static_cast<std::ptrdiff_t>(i)).value() : j[i], rng,
        depth + 1);
    return;
  }
  static const std::vector<Json> replacements = {nullptr,
                                                 -1,
                                                 0,
                                                 1.5,
                                                 1e308,
                                                 -1e308,
                                                 Json(UINT64_MAX),
                                                 Json(INT64_MIN),
                                                 "x",
                                                 "O(3)",
                                                 "a7",
                                                 Json::array(),
                                                 Json::array({1, 2}),
                                                 Json::array({1e300, 2, 3}),
                                                 Json::object(),
                                                 true};
  j = replacements[rng() % replacements.size()];
}

std::string mutateJsonText(const std::string& text, std::mt19937& rng) {
  Json j = Json::parse(text);
  const int repeats = 1 + static_cast<int>(rng() % 3);
  for (int r = 0; r < repeats; ++r) mutateJsonTree(j, rng);
  return j.dump();
}

class DecodeFuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(61);
    graph_ = testing::makeRandomGraph(rng, {8, 4, 12, 2, 30, 40});
    update_ = testing::makeRandomUpdate(rng);
  }
  SceneGraph graph_;
  RobotUpdate update_;
};

const Decoder kBinaryGraph = [](const std::string& s) {
  return decodeSceneGraphBinary(s).status();
};
const Decoder kBinaryUpdate = [](const std::string& s) {
  return decodeRobotUpdateBinary(s).status();
};
const Decoder kJsonGraph = [](const std::string& s) { return sceneGraphFromJson(s).status(); };
const Decoder kJsonUpdate = [](const std::string& s) { return robotUpdateFromJson(s).status(); };
const Decoder kSparkGraph = [](const std::string& s) {
  return sceneGraphFromSparkJson(s).status();
};

TEST_F(DecodeFuzz, BinaryBytes) {
  std::mt19937 rng(62);
  Tally tally;
  const std::string graph = encodeSceneGraphBinary(graph_);
  const std::string update = encodeRobotUpdateBinary(update_);
  for (int i = 0; i < 2000; ++i) {
    check(kBinaryGraph, testing::mutateBytes(graph, rng), tally);
    check(kBinaryUpdate, testing::mutateBytes(update, rng), tally);
  }
  EXPECT_GT(tally.rejected, 3000);
}

// Mutated payloads in valid frames reach the field decoders; some still decode.
TEST_F(DecodeFuzz, BinaryPayloads) {
  std::mt19937 rng(63);
  Tally tally;
  const std::string graph = payloadOf(encodeSceneGraphBinary(graph_));
  const std::string update = payloadOf(encodeRobotUpdateBinary(update_));
  for (int i = 0; i < 3000; ++i) {
    check(kBinaryGraph, frame(RecordKind::kSceneGraph, testing::mutateBytes(graph, rng)), tally);
    check(kBinaryUpdate, frame(RecordKind::kRobotUpdate, testing::mutateBytes(update, rng)), tally);
  }
  EXPECT_GT(tally.rejected, 1000);
  EXPECT_GT(tally.decoded, 50);
}

TEST_F(DecodeFuzz, JsonTrees) {
  std::mt19937 rng(64);
  Tally tally;
  const std::string graph = sceneGraphToJson(graph_, true);
  const std::string update = robotUpdateToJson(update_, true);
  const std::string spark = sceneGraphToSparkJson(graph_);
  for (int i = 0; i < 1500; ++i) {
    check(kJsonGraph, mutateJsonText(graph, rng), tally);
    check(kJsonUpdate, mutateJsonText(update, rng), tally);
    check(kSparkGraph, mutateJsonText(spark, rng), tally);
  }
  EXPECT_GT(tally.rejected, 1000);
  EXPECT_GT(tally.decoded, 100);
}

TEST_F(DecodeFuzz, JsonBytes) {
  std::mt19937 rng(65);
  Tally tally;
  const std::string graph = sceneGraphToJson(graph_);
  const std::string spark = sceneGraphToSparkJson(graph_);
  for (int i = 0; i < 1000; ++i) {
    check(kJsonGraph, testing::mutateBytes(graph, rng), tally);
    check(kSparkGraph, testing::mutateBytes(spark, rng), tally);
  }
  EXPECT_GT(tally.rejected, 1000);
}

// Spark-DSG's binary layout in every version, mutated: decoded (and the decoded graph imported)
// or refused with the byte and field, never a crash. The random graph goes with its mesh.
TEST_F(DecodeFuzz, SparkBinaryBytesInEveryVersion) {
  std::mt19937 rng(66);
  Tally tally;
  const spark::Graph graph = sparkFromSceneGraph(graph_, true);
  const std::vector<spark::Version> versions = {{1, 0, 2}, {1, 0, 3}, {1, 0, 4}, {1, 0, 5},
                                                {1, 0, 6}, {1, 1, 0}, {1, 1, 1}, {1, 1, 2},
                                                {1, 1, 3}, {1, 1, 4}};
  for (const spark::Version& v : versions) {
    const std::string wire = spark::encodeWire(graph, v);
    ASSERT_TRUE(spark::decodeWire(wire, v)) << v.str();
    const Decoder decode = [v](const std::string& bytes) -> Status {
      auto decoded = spark::decodeWire(bytes, v);
      if (!decoded) return Status(Error{decoded.error()});
      return sceneGraphFromSpark(decoded.value()).status();
    };
    for (int i = 0; i < 400; ++i) check(decode, testing::mutateBytes(wire, rng), tally);
  }
  EXPECT_GT(tally.rejected, 3000);
  EXPECT_GT(tally.decoded, 20);
}

}  // namespace
}  // namespace hydra_multi::io
