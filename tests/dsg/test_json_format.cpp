#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/dsg/io/json_fields.h"
#include "hydra_multi/dsg/io/json_format.h"
#include "support/random_graphs.h"

namespace hydra_multi::io {
namespace {

// Every attribute survives our JSON exactly, in both layouts.
TEST(JsonFormat, SceneGraphRoundTripIsExact) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 10; ++trial) {
    const SceneGraph graph = testing::makeRandomGraph(rng);
    for (const bool one_line : {false, true}) {
      const auto decoded = sceneGraphFromJson(sceneGraphToJson(graph, one_line));
      ASSERT_TRUE(decoded.ok()) << decoded.error();
      EXPECT_EQ(decoded.value(), graph);
    }
  }
}

TEST(JsonFormat, RobotUpdateRoundTripIsExact) {
  std::mt19937 rng(32);
  for (int trial = 0; trial < 10; ++trial) {
    const RobotUpdate update = testing::makeRandomUpdate(rng, static_cast<uint64_t>(trial));
    const auto decoded = robotUpdateFromJson(robotUpdateToJson(update));
    ASSERT_TRUE(decoded.ok()) << decoded.error();
    EXPECT_EQ(decoded.value(), update);
  }
}

// Floats are written with their shortest form and still read back to the same float.
TEST(JsonFormat, FloatsAreShortAndExact) {
  std::mt19937 rng(33);
  std::uniform_real_distribution<float> u(-1000.0f, 1000.0f);
  for (int i = 0; i < 100000; ++i) {
    const float f = u(rng);
    EXPECT_EQ(static_cast<float>(floatForJson(f)), f);
  }
  EXPECT_EQ(floatForJson(0.1f), 0.1);
}

std::string errorOf(const std::string& text) {
  const auto decoded = sceneGraphFromJson(text);
  EXPECT_FALSE(decoded.ok());
  return decoded.error();
}

// Errors say what was wrong and where (item and key, or byte of a syntax error).
TEST(JsonFormat, ErrorsNameWhatAndWhere) {
  std::mt19937 rng(34);
  const std::string good = sceneGraphToJson(testing::makeRandomGraph(rng), true);
  EXPECT_NE(errorOf(good.substr(0, good.size() / 2)).find("invalid JSON at byte"),
            std::string::npos);
  EXPECT_NE(errorOf("[]").find("format"), std::string::npos);

  const std::string header = R"J({"format": "hydra-multi scene graph", "version": 1, )J";
  EXPECT_NE(errorOf(R"J({"format": "hydra-multi scene graph", "version": 2})J")
                .find("version 2 is not supported"),
            std::string::npos);
  const std::string missing = errorOf(header + R"J("nodes": [{"id": "O(1)", "layer": "objects"}],
      "edges": [], "mesh": {"vertices": [], "faces": []}})J");
  EXPECT_NE(missing.find("nodes[0]: missing key 'position'"), std::string::npos) << missing;

  const std::string bad_id = errorOf(header + R"J("nodes": [{"id": "O(1", "layer": "objects"}],
      "edges": [], "mesh": {"vertices": [], "faces": []}})J");
  EXPECT_NE(bad_id.find("'O(1' is not a node id"), std::string::npos) << bad_id;

  const std::string dangling = errorOf(header + R"J("nodes": [], "edges": [{"source": "O(1)",
      "target": "p(2)", "weight": 1.0, "weighted": false}], "mesh": {"vertices": [], "faces": []}})J");
  EXPECT_NE(dangling.find("edge 0 (O(1) - p(2)): endpoint O(1) does not exist"), std::string::npos)
      << dangling;

  const std::string infinite = errorOf(header + R"J("nodes": [{"id": "O(1)", "layer": "objects",
      "position": [1e999, 0, 0], "last_update_time_ns": 0, "is_active": true, "label": 1,
      "name": "", "color": [0, 0, 0], "bounding_box": null, "mesh_vertices": []}], "edges": [],
      "mesh": {"vertices": [], "faces": []}})J");
  EXPECT_NE(infinite.find("number overflow"), std::string::npos) << infinite;

  const std::string face = errorOf(header + R"J("nodes": [], "edges": [], "mesh": {"vertices": [],
      "faces": [[0, 1, 2]]}})J");
  EXPECT_NE(face.find("mesh face 0"), std::string::npos) << face;
}

TEST(JsonFormat, RobotUpdateErrors) {
  std::mt19937 rng(35);
  std::string text = robotUpdateToJson(testing::makeRandomUpdate(rng), true);
  const std::string needle = R"J("robot":"b")J";
  text.replace(text.find(needle), needle.size(), R"J("robot":"p")J");
  const auto decoded = robotUpdateFromJson(text);
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("'p' is not a robot name"), std::string::npos) << decoded.error();
}

}  // namespace
}  // namespace hydra_multi::io
