// The station over a team whose first robot is missing or late: the others are never dropped;
// the global frame is the first robot's with data, and moves to robot a's once a is aligned.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <thread>

#include "hydra_multi/sim/dataset.h"
#include "hydra_multi/station/station.h"

namespace hydra_multi {
namespace {

const RobotId kA(0), kB(1);

// The tiny team's streams as the station replays them, every robot's updates by time; robot a's
// updates for which `drop` holds left out (a damaged record).
DatasetStreams tinyStreams(size_t snapshot_every,
                           const std::function<bool(const RobotUpdate&)>& drop) {
  sim::SimulationConfig config = sim::presetConfig("tiny", 1).value();
  config.mapper.snapshot_every = snapshot_every;
  const sim::SimulatedDataset dataset = sim::simulateDataset(config).value();
  DatasetStreams streams;
  for (size_t r = 0; r < dataset.streams.size(); ++r) {
    streams.robots.push_back(RobotId(static_cast<uint8_t>(r)));
    for (const RobotUpdate& u : dataset.streams[r])
      if (!(u.robot == kA && drop(u))) streams.updates.push_back(u);
  }
  std::stable_sort(
      streams.updates.begin(), streams.updates.end(),
      [](const RobotUpdate& a, const RobotUpdate& b) { return a.time_ns < b.time_ns; });
  return streams;
}

size_t nodesOf(const SceneGraph& graph, RobotId robot) { return graph.nodesOfRobot(robot).size(); }

// The tiny team with robot a's first update lost (snapshots every `snapshot_every` updates), run
// through the station; its log lines in `log`.
StationResult withoutAsFirstUpdate(size_t snapshot_every, std::vector<std::string>& log) {
  const DatasetStreams streams =
      tinyStreams(snapshot_every, [](const RobotUpdate& u) { return u.sequence == 0; });
  StationOptions options;
  options.log = [&log](const std::string& line) { log.push_back(line); };
  return runStation(streams, options);
}

bool logged(const std::vector<std::string>& log, const std::string& line) {
  return std::find(log.begin(), log.end(), line) != log.end();
}

// Robot a's first update lost and no snapshot after it: the map is robot b's, in b's frame (it
// was empty: the frame was a's, which nothing placed).
TEST(Station, RobotAMissingTheMapIsTheOthers) {
  std::vector<std::string> log;
  const StationResult result = withoutAsFirstUpdate(0, log);
  EXPECT_EQ(result.global_robot, kB);
  EXPECT_GT(nodesOf(result.graph, kB), 100u);
  EXPECT_EQ(nodesOf(result.graph, kA), 0u);
  EXPECT_TRUE(
      logged(log, "station: the global frame is robot b's: the station has no update of a yet"));
  // The robot that never arrived is named with what became of its updates.
  const auto named = std::find_if(log.begin(), log.end(), [](const std::string& line) {
    return line.rfind("robot a: updates 0 applied of ", 0) == 0;
  });
  ASSERT_NE(named, log.end());
  EXPECT_NE(named->find("waiting for a snapshot"), std::string::npos) << *named;
}

// Robot a's first update lost, but a sends a snapshot every 4 updates: a joins at its next one, is
// aligned with b, and the global frame moves to a's; both robots are in the map.
TEST(Station, RobotAJoiningLateTakesTheGlobalFrameOnceAligned) {
  std::vector<std::string> log;
  const StationResult result = withoutAsFirstUpdate(4, log);
  EXPECT_EQ(result.global_robot, kA);
  EXPECT_GT(nodesOf(result.graph, kA), 100u);
  EXPECT_GT(nodesOf(result.graph, kB), 100u);
  EXPECT_EQ(result.aligned.size(), 2u);
  EXPECT_TRUE(logged(log, "station: the global frame moves to robot a's (aligned with robot b)"));
  // In a's frame: a's first keyframe there is where a's own frame has it (near its origin).
  const auto first = std::min_element(result.keyframe_stamps.begin(), result.keyframe_stamps.end(),
                                      [](const auto& x, const auto& y) {
                                        return x.first.sourceRobot() == kA &&
                                               (y.first.sourceRobot() != kA || x.second < y.second);
                                      });
  ASSERT_EQ(first->first.sourceRobot(), kA);
  ASSERT_TRUE(result.graph.hasNode(first->first));
  EXPECT_LT(result.graph.getNode(first->first).position.norm(), 1.0);
}

// A team the station has nothing of: an empty map, no round fails.
TEST(Station, NoUpdateAtAll) {
  const DatasetStreams streams = tinyStreams(0, [](const RobotUpdate&) { return true; });
  DatasetStreams none = streams;
  none.updates.clear();
  const StationResult result = runStation(none);
  EXPECT_EQ(result.graph.numNodes(), 0u);
  EXPECT_EQ(result.global_robot, kA);
}

// Two inputs at once: each robot's updates submitted from its own thread. Every update is
// applied, the frontend ends with every keyframe of the file replay, and both robots are aligned;
// after finish() the station takes no more.
TEST(Station, InputsFromSeveralThreads) {
  const DatasetStreams streams = tinyStreams(0, [](const RobotUpdate&) { return false; });
  const StationResult replayed = runStation(streams);
  std::vector<std::string> log;
  StationOptions options;
  options.log = [&log](const std::string& line) { log.push_back(line); };  // one line at a time
  Station station(options, streams.robots);
  std::vector<std::thread> inputs;
  for (const RobotId robot : streams.robots) {
    inputs.emplace_back([&station, &streams, robot] {
      for (const RobotUpdate& u : streams.updates) {
        if (u.robot == robot) {
          ASSERT_TRUE(station.submit(u));
        }
      }
    });
  }
  for (std::thread& input : inputs) input.join();
  const StationResult result = station.finish();
  EXPECT_FALSE(station.submit(streams.updates.front()));
  EXPECT_EQ(result.counts.offered, streams.updates.size());
  EXPECT_EQ(result.counts.appliedTotal(), streams.updates.size());
  EXPECT_EQ(result.updates.size(), streams.updates.size());
  EXPECT_EQ(result.keyframe_stamps, replayed.keyframe_stamps);
  EXPECT_EQ(result.aligned.size(), 2u);
  EXPECT_EQ(result.global_robot, kA);
  EXPECT_FALSE(log.empty());
}

// Each round but the last reports the freed memory the allocator held after it, handed back where
// that was over the budget (memory.keep_freed_mb, here 1 MB); the last round, after which the
// station hands everything back, reports none. Without jemalloc, or with MALLOC_CONF set, nothing
// is kept, so nothing is handed back.
TEST(Station, EachRoundReportsTheFreedMemoryKeptOrHandedBack) {
  const DatasetStreams streams = tinyStreams(0, [](const RobotUpdate&) { return false; });
  StationOptions options;
  options.keep_freed_mb = 1;
  const StationResult result = runStation(streams, options);
  ASSERT_GE(result.rounds.size(), 2u);
  EXPECT_EQ(result.rounds.back().freed.bytes, 0u);
  EXPECT_FALSE(result.rounds.back().freed.handed_back);
#ifdef HYDRA_MULTI_JEMALLOC
  const bool kept = std::getenv("MALLOC_CONF") == nullptr;
#else
  const bool kept = false;
#endif
  size_t reported = 0, handed_back = 0;
  for (size_t i = 0; i + 1 < result.rounds.size(); ++i) {
    const FreedMemory& freed = result.rounds[i].freed;
    EXPECT_EQ(freed.handed_back, kept && freed.bytes > (size_t{1} << 20)) << "round " << i;
    reported += freed.bytes > 0;
    handed_back += freed.handed_back;
  }
  if (kept) {
    EXPECT_GT(reported, 0u);
    EXPECT_GT(handed_back, 0u);
  }
}

}  // namespace
}  // namespace hydra_multi
