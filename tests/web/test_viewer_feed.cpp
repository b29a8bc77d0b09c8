#include "hydra_multi/web/viewer_feed.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "web/round_fixture.h"

namespace hydra_multi::web {
namespace {

using nlohmann::json;
using testing::RoundFixture;

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("hm_feed_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// A run of `rounds` views of a graph that grows and moves.
std::vector<ViewState> rounds(size_t count) {
  RoundFixture f(5, {40, 10, 60, 3, 100, 150});
  std::vector<ViewState> views;
  for (size_t r = 0; r < count; ++r) {
    f.timing.round = r;
    for (const NodeId id : f.graph.nodesInLayer(Layer::kAgents))
      f.graph.findMutableNode(id)->position.x() += 0.05 * double(r % 3);
    f.graph.addOrUpdateNode(makeNode(NodeId('O', 100 + r), Layer::kObjects, {double(r), 0, 0}));
    views.push_back(viewOfRound(f.output()));
  }
  return views;
}

// The view as published, without the wall-clock stamp the feed adds.
ViewState unstamped(const std::string& snapshot) {
  ViewState view;
  EXPECT_TRUE(applyViewDelta(view, json::parse(snapshot)));
  view.info.erase("published_unix_ms");
  return view;
}

TEST(ViewerFeed, EveryViewComesBackFromCheckpointsAndDeltas) {
  const std::vector<ViewState> views = rounds(30);
  ViewerFeed feed;
  for (const ViewState& v : views) feed.publish(v);
  ASSERT_EQ(feed.latest(), views.size());
  EXPECT_GT(feed.checkpoints(), 1u);
  EXPECT_LT(feed.checkpoints(), views.size() / 2) << "a checkpoint for every few views only";
  for (size_t seq = 1; seq <= views.size(); ++seq) {
    ViewState expected = views[seq - 1];
    expected.seq = seq;
    EXPECT_EQ(unstamped(feed.snapshot(seq).value()), expected) << "view " << seq;
  }
  EXPECT_FALSE(feed.snapshot(views.size() + 1));
  EXPECT_EQ(feed.deltasAfter(27).size(), 3u);
  EXPECT_TRUE(feed.deltasAfter(30).empty());
  EXPECT_TRUE(feed.waitNewer(29, std::chrono::milliseconds(0)));
  EXPECT_FALSE(feed.waitNewer(30, std::chrono::milliseconds(10)));
  feed.finish();
  EXPECT_TRUE(feed.ended());
  EXPECT_EQ(feed.latest(), 31u);
  EXPECT_TRUE(json::parse(feed.snapshot().value())["final"].get<bool>());
  const json summaries = json::parse(feed.roundsJson());
  EXPECT_EQ(summaries["rounds"].size(), 31u);
  EXPECT_EQ(summaries["epoch"], feed.epoch());
}

TEST(ViewerFeed, HistoryFileReadsBackTheSameFeed) {
  const std::string path = tempPath("history.jsonl");
  const std::vector<ViewState> views = rounds(8);
  std::string epoch;
  std::vector<std::string> snapshots;
  {
    ViewerFeed feed(path);
    for (const ViewState& v : views) feed.publish(v);
    feed.finish();
    epoch = feed.epoch();
    for (uint64_t s = 1; s <= feed.latest(); ++s) snapshots.push_back(*feed.snapshot(s));
  }
  auto loaded = ViewerFeed::load(path);
  ASSERT_TRUE(loaded) << loaded.error();
  EXPECT_EQ(loaded.value()->epoch(), epoch);
  EXPECT_TRUE(loaded.value()->ended());
  ASSERT_EQ(loaded.value()->latest(), snapshots.size());
  for (uint64_t s = 1; s <= snapshots.size(); ++s)
    EXPECT_EQ(*loaded.value()->snapshot(s), snapshots[s - 1]) << "view " << s;
  std::filesystem::remove(path);
}

TEST(ViewerFeed, DamagedHistoryNamesTheLine) {
  const std::string path = tempPath("damaged.jsonl");
  {
    ViewerFeed feed(path);
    for (const ViewState& v : rounds(3)) feed.publish(v);
  }
  std::vector<std::string> lines;
  {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_EQ(lines.size(), 4u);
  const auto write = [&](const std::vector<std::string>& content) {
    std::ofstream out(path, std::ios::trunc);
    for (const std::string& l : content) out << l << "\n";
  };
  const auto refusedAt = [&](const std::string& where) {
    auto loaded = ViewerFeed::load(path);
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().find(where), std::string::npos) << loaded.error();
  };
  write({lines[0], lines[1], lines[2], lines[3].substr(0, lines[3].size() / 2)});
  refusedAt("line 4: not JSON");
  write({lines[0], lines[1], lines[3]});
  refusedAt("line 3: sequence 3 after 1");
  write({R"({"format":"something else"})", lines[1]});
  refusedAt("line 1: not a viewer history");
  write({lines[0], lines[1], R"({"seq":2})"});
  refusedAt("line 3: viewer delta: 'round'");
  EXPECT_FALSE(ViewerFeed::load(path + ".missing"));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hydra_multi::web
