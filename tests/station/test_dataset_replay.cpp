// File replay of a dataset's streams: the robots' updates merged by time; a damaged record or an
// update of the wrong robot is skipped and named (file, byte, why), the rest is read; a dataset
// that cannot be replayed at all is an error naming the file.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/station/dataset_replay.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

namespace fs = std::filesystem;

class DatasetReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hydra_multi_replay_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    manifest(R"([{"robot": "a", "stream": "a.dsgb", "updates": 4},
                  {"robot": "b", "stream": "b.dsgb", "updates": 4}])");
    std::mt19937 rng(31);
    for (const char robot : {'a', 'b'}) {
      std::string& stream = streams_[robot];
      for (uint64_t i = 0; i < 4; ++i) {
        RobotUpdate u = testing::makeRandomUpdate(rng, i);
        u.robot = *RobotId::parse(std::string(1, robot));
        u.time_ns = static_cast<int64_t>(10 * i + (robot == 'b' ? 5 : 0));
        starts_[robot].push_back(stream.size());
        stream += io::encodeRobotUpdateBinary(u);
      }
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  // dataset.json with this "robots" list.
  void manifest(const std::string& robots) const {
    std::ofstream(dir_ / "dataset.json")
        << R"({"format": "hydra-multi-dataset", "robots": )" << robots << "}";
  }
  void write(char robot, const std::string& bytes) const {
    std::ofstream(dir_ / (std::string(1, robot) + ".dsgb"), std::ios::binary) << bytes;
  }
  std::string path(char robot) const { return (dir_ / (std::string(1, robot) + ".dsgb")).string(); }

  fs::path dir_;
  std::map<char, std::string> streams_;
  std::map<char, std::vector<size_t>> starts_;
};

std::vector<std::string> arrivals(const DatasetStreams& streams) {
  std::vector<std::string> order;
  for (const RobotUpdate& u : streams.updates)
    order.push_back(u.robot.str() + std::to_string(u.sequence));
  return order;
}

TEST_F(DatasetReplay, UpdatesOfAllRobotsByTime) {
  write('a', streams_['a']);
  write('b', streams_['b']);
  const auto streams = loadDatasetStreams(dir_.string());
  ASSERT_TRUE(streams.ok()) << streams.error();
  EXPECT_EQ(arrivals(streams.value()),
            (std::vector<std::string>{"a0", "b0", "a1", "b1", "a2", "b2", "a3", "b3"}));
  EXPECT_TRUE(streams.value().skipped.empty());
  EXPECT_EQ(streams.value().bytes, streams_['a'].size() + streams_['b'].size());
}

// One flipped byte in b's second update and a cut-off end of a's stream: those two records are
// left out and named, every other update is read.
TEST_F(DatasetReplay, DamagedRecordsAreSkippedAndNamed) {
  std::string a = streams_['a'];
  std::string b = streams_['b'];
  b[(starts_['b'][1] + starts_['b'][2]) / 2] ^= 0x21;
  write('a', a.substr(0, a.size() - 3));
  write('b', b);
  const auto streams = loadDatasetStreams(dir_.string());
  ASSERT_TRUE(streams.ok()) << streams.error();
  EXPECT_EQ(arrivals(streams.value()),
            (std::vector<std::string>{"a0", "b0", "a1", "a2", "b2", "b3"}));
  const std::vector<std::string>& skipped = streams.value().skipped;
  ASSERT_EQ(skipped.size(), 2u);
  EXPECT_EQ(skipped[0].rfind(path('a') + ": record at byte " + std::to_string(starts_['a'][3]), 0),
            0u)
      << skipped[0];
  EXPECT_NE(skipped[0].find("truncated"), std::string::npos) << skipped[0];
  EXPECT_EQ(skipped[1].rfind(path('b') + ": record at byte " + std::to_string(starts_['b'][1]), 0),
            0u)
      << skipped[1];
  EXPECT_NE(skipped[1].find("checksum mismatch"), std::string::npos) << skipped[1];
}

// An update that names another robot than its stream's is not replayed as either.
TEST_F(DatasetReplay, UpdateOfAnotherRobotIsSkipped) {
  std::mt19937 rng(32);
  RobotUpdate stray = testing::makeRandomUpdate(rng, 4);
  stray.robot = *RobotId::parse("c");
  write('a', streams_['a'] + io::encodeRobotUpdateBinary(stray));
  write('b', streams_['b']);
  const auto streams = loadDatasetStreams(dir_.string());
  ASSERT_TRUE(streams.ok()) << streams.error();
  EXPECT_EQ(streams.value().updates.size(), 8u);
  ASSERT_EQ(streams.value().skipped.size(), 1u);
  EXPECT_EQ(streams.value().skipped[0], path('a') + ": update 4 is from robot c, not a");
}

// An intact record whose update holds a NaN (a robot's estimator diverged) is left out the same
// way, named by its update, what is wrong and where.
TEST_F(DatasetReplay, UpdateWithNaNIsSkipped) {
  std::mt19937 rng(33);
  RobotUpdate diverged = testing::makeRandomUpdate(rng, 4);
  diverged.robot = *RobotId::parse("b");
  diverged.time_ns = 45;
  ASSERT_FALSE(diverged.graph.mesh.vertices.empty());
  diverged.graph.mesh.vertices[1].position.y() = std::nan("");
  write('a', streams_['a']);
  write('b', streams_['b'] + io::encodeRobotUpdateBinary(diverged));
  const auto streams = loadDatasetStreams(dir_.string());
  ASSERT_TRUE(streams.ok()) << streams.error();
  EXPECT_EQ(streams.value().updates.size(), 8u);
  ASSERT_EQ(streams.value().skipped.size(), 1u);
  const std::string& why = streams.value().skipped[0];
  EXPECT_EQ(why.rfind(path('b') + ": robot update record at byte " +
                          std::to_string(streams_['b'].size()) + ": update 4 of robot b",
                      0),
            0u)
      << why;
  EXPECT_NE(why.find("mesh vertex 1: position is not finite"), std::string::npos) << why;
}

// A stream that yields no update, or fewer than dataset.json says the robot sent, is named in a
// warning; the replay goes on with what there is.
TEST_F(DatasetReplay, StreamsShorterThanSentAreNamed) {
  write('a', "");
  write('b', streams_['b'].substr(0, starts_['b'][3]));
  const auto streams = loadDatasetStreams(dir_.string());
  ASSERT_TRUE(streams.ok()) << streams.error();
  EXPECT_EQ(arrivals(streams.value()), (std::vector<std::string>{"b0", "b1", "b2"}));
  EXPECT_EQ(streams.value().warnings,
            (std::vector<std::string>{
                "robot a: " + path('a') + " holds no intact update of robot a",
                "robot b: " + path('b') + " holds 3 intact updates, " +
                    (dir_ / "dataset.json").string() + " says it sent 4"}));
}

TEST_F(DatasetReplay, DatasetThatCannotBeReplayedIsAnError) {
  write('a', streams_['a']);
  const auto missing_stream = loadDatasetStreams(dir_.string());
  ASSERT_FALSE(missing_stream.ok());
  EXPECT_NE(missing_stream.error().find(path('b')), std::string::npos) << missing_stream.error();

  // dataset.json's team: each error names the file, the entry and what is wrong.
  const std::string header = (dir_ / "dataset.json").string();
  const std::vector<std::pair<std::string, std::string>> refused = {
      {R"([{"robot": "?", "stream": "a.dsgb"}])", ": robots[0]: unknown robot '?'"},
      {R"([{"robot": "a"}])", ": robots[0]: no \"stream\" path"},
      {R"([])", ": the \"robots\" list is empty: no robot to replay"},
      {R"([{"robot": "a", "stream": "a.dsgb"}, {"robot": "a", "stream": "b.dsgb"}])",
       ": robots[1]: robot a is listed twice"},
      {R"([{"robot": "a", "stream": "../a.dsgb"}])",
       ": robots[0]: stream '../a.dsgb' is not a relative path inside the dataset's folder"},
      {R"([{"robot": "a", "stream": "/etc/passwd"}])",
       ": robots[0]: stream '/etc/passwd' is not a relative path inside the dataset's folder"},
      {R"([{"robot": "a", "stream": "a.dsgb", "updates": -4}])",
       ": robots[0]: \"updates\" is not a count"},
      {R"({"a": "a.dsgb"})", ": no \"robots\" list"}};
  for (const auto& [robots, error] : refused) {
    manifest(robots);
    const auto streams = loadDatasetStreams(dir_.string());
    ASSERT_FALSE(streams.ok()) << robots;
    EXPECT_EQ(streams.error(), header + error) << robots;
  }
  std::ofstream(dir_ / "dataset.json") << R"({"robots": [{"robot": "a", "stream": "a.dsgb"}]})";
  const auto unformatted = loadDatasetStreams(dir_.string());
  ASSERT_FALSE(unformatted.ok());
  EXPECT_NE(unformatted.error().find("not a hydra-multi dataset"), std::string::npos)
      << unformatted.error();

  const auto not_a_dataset = loadDatasetStreams((dir_ / "nowhere").string());
  ASSERT_FALSE(not_a_dataset.ok());
  EXPECT_NE(not_a_dataset.error().find("is " + (dir_ / "nowhere").string() + " a dataset"),
            std::string::npos)
      << not_a_dataset.error();
}

}  // namespace
}  // namespace hydra_multi
