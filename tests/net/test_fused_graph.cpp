// The fused graph in the clone pattern: a subscriber's state takes a snapshot, then the deltas
// that follow it; an older one is stale, a later one a gap and one that does not apply broken
// (both ask for a snapshot), leaving the graph as it was. On loopback, a watcher that joins after
// two rounds gets the whole state by a snapshot, then the deltas, and ends with the publisher's
// last graph when it closes.

#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "hydra_multi/net/fused_graph.h"
#include "support/random_graphs.h"

namespace hydra_multi::net {
namespace {

using namespace std::chrono_literals;

FusedSummary numbered(uint64_t sequence) {
  FusedSummary s;
  s.sequence = sequence;
  return s;
}

TEST(FusedGraph, WatchStateTakesWhatFollows) {
  std::mt19937 rng(31);
  const SceneGraph g3 = testing::makeRandomGraph(rng), g4 = testing::makeRandomGraph(rng);
  WatchState state;
  EXPECT_EQ(state.onDelta(numbered(1), diffGraphs(SceneGraph(), g3)), WatchState::Outcome::kGap);
  EXPECT_EQ(state.onSnapshot(numbered(3), g3), WatchState::Outcome::kApplied);
  EXPECT_EQ(state.onSnapshot(numbered(2), SceneGraph()), WatchState::Outcome::kStale);
  EXPECT_EQ(state.onDelta(numbered(3), diffGraphs(g3, g4)), WatchState::Outcome::kStale);
  EXPECT_EQ(state.onDelta(numbered(5), diffGraphs(g3, g4)), WatchState::Outcome::kGap);
  GraphDelta broken = diffGraphs(g3, g4);
  broken.mesh.vertex_start = g3.mesh().vertices.size() + 10;  // past the mesh it has
  EXPECT_EQ(state.onDelta(numbered(4), broken), WatchState::Outcome::kBroken);
  EXPECT_EQ(state.graph(), g3);
  EXPECT_EQ(state.sequence(), 3u);
  EXPECT_EQ(state.onDelta(numbered(4), diffGraphs(g3, g4)), WatchState::Outcome::kApplied);
  EXPECT_EQ(state.graph(), g4);
}

TEST(FusedGraph, LateWatcherGetsTheWholeStateThenTheDeltas) {
  std::mt19937 rng(32);
  std::vector<SceneGraph> rounds;
  for (int i = 0; i < 4; ++i) rounds.push_back(testing::makeRandomGraph(rng));
  auto publisher = GraphPublisher::create({}).value();
  publisher->publish(rounds[0], 0, 2, 1);
  std::this_thread::sleep_for(50ms);  // each round published, not overtaken by the next
  publisher->publish(rounds[1], 1, 2, 2);
  const auto until = std::chrono::steady_clock::now() + 2s;
  while (publisher->published() < 2 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(10ms);
  ASSERT_EQ(publisher->published(), 2u);

  GraphWatcher watcher({publisher->endpoint(), 5.0, {}});
  std::vector<uint64_t> seen;
  const auto each = [&](const WatchState& s) { seen.push_back(s.sequence()); };
  ASSERT_TRUE(watcher.pump(500ms, each).ok());  // the snapshot, and the SUB connected
  ASSERT_EQ(seen, std::vector<uint64_t>{2});
  EXPECT_EQ(watcher.state().graph(), rounds[1]);
  EXPECT_EQ(watcher.state().summary().robots_aligned, 2u);
  for (int i = 2; i < 4; ++i) {
    publisher->publish(rounds[i], static_cast<size_t>(i), 2, 2);
    ASSERT_TRUE(watcher.pump(300ms, each).ok());
  }
  publisher->close();
  for (int i = 0; i < 20 && !watcher.ended(); ++i) ASSERT_TRUE(watcher.pump(100ms, each).ok());
  EXPECT_TRUE(watcher.ended());
  EXPECT_EQ(watcher.state().graph(), rounds[3]);
  EXPECT_EQ(seen.back(), 5u);  // two rounds, the snapshot of the second, two more, the end
  EXPECT_TRUE(watcher.state().summary().final);
}

TEST(FusedGraph, WatcherSaysWhenNobodyAnswers) {
  std::string endpoint;
  {
    auto probe = GraphPublisher::create({}).value();
    endpoint = probe->endpoint();
  }  // gone: nobody answers there
  GraphWatcher watcher({endpoint, 0.3, {}});
  Status status = Status::Ok();
  for (int i = 0; i < 10 && status.ok(); ++i) status = watcher.pump(100ms, {});
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.message(), endpoint + ": no answer to a snapshot request within 0.3 s");
}

}  // namespace
}  // namespace hydra_multi::net
