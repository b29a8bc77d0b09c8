// The bandwidth ledger on the tiny team: each update's bytes are its record's, a full resend is
// the encoding of the robot's whole map at that update, a gap leaves updates without that figure
// until a snapshot, and the CSV and SVG hold a line per update and per robot and kind.

#include <gtest/gtest.h>

#include <algorithm>

#include "hydra_multi/sim/dataset.h"
#include "hydra_multi/station/bandwidth.h"

namespace hydra_multi {
namespace {

const sim::SimulatedDataset& tiny() {
  static const sim::SimulatedDataset dataset =
      sim::simulateDataset(sim::presetConfig("tiny", 1).value()).value();
  return dataset;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Bandwidth, FullResendIsTheWholeMapAtEachUpdate) {
  constexpr size_t kFraming = 20;
  BandwidthLedger ledger(kFraming);
  size_t total = 0;
  for (const auto& stream : tiny().streams) {
    // Arrival order does not matter: a robot's updates are taken by sequence.
    for (auto it = stream.rbegin(); it != stream.rend(); ++it) ledger.add(*it);
    total += stream.size();
  }
  const std::vector<UpdateBandwidth> rows = ledger.rows();
  ASSERT_EQ(rows.size(), total);
  // By robot, then sequence (the robots' maps are replayed side by side).
  EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return a.robot != b.robot ? a.robot < b.robot : a.sequence < b.sequence;
  }));
  for (size_t r = 0; r < tiny().streams.size(); ++r) {
    const std::vector<RobotUpdate>& stream = tiny().streams[r];
    RobotStreamState map;
    for (const RobotUpdate& u : stream) {
      ASSERT_TRUE(map.add(u).ok());
      const auto row = std::find_if(rows.begin(), rows.end(), [&](const UpdateBandwidth& b) {
        return b.robot == u.robot && b.sequence == u.sequence;
      });
      ASSERT_NE(row, rows.end());
      EXPECT_EQ(row->record_bytes, io::encodeRobotUpdateBinary(u).size() + kFraming);
      EXPECT_EQ(row->wire_bytes, row->record_bytes);  // no message bytes given
      EXPECT_EQ(row->parts.total() + kFraming, row->record_bytes);
      ASSERT_TRUE(row->full_resend_bytes.has_value());
      EXPECT_EQ(*row->full_resend_bytes,
                io::encodeRobotUpdateBinary(map.snapshot()).size() + kFraming);
    }
    // The first update is the whole map: as a full resend it costs what it costs.
    EXPECT_TRUE(stream.front().is_snapshot);
  }
  const auto totals = bandwidthTotals(rows);
  ASSERT_EQ(totals.size(), 2u);
  for (const auto& [robot, t] : totals) {
    EXPECT_EQ(t.without_full_resend, 0u);
    EXPECT_GT(t.full_resend_bytes, 4 * t.record_bytes) << robot.str();
  }
  const std::string csv = bandwidthCsv(rows);
  EXPECT_EQ(count(csv, "\n"), total + 1);
  EXPECT_EQ(csv.rfind("robot,sequence,time_s,kind,wire_bytes,record_bytes,", 0), 0u);
  const std::string svg = bandwidthSvg(rows);
  EXPECT_EQ(count(svg, "<polyline class=\"ours\""), 2u);
  EXPECT_EQ(count(svg, "<polyline class=\"full\""), 2u);
  EXPECT_EQ(count(svg, "<polyline class=\"wire\""), 0u);  // nothing came compressed
}

TEST(Bandwidth, NoUpdatesNoRows) { EXPECT_TRUE(BandwidthLedger().rows().empty()); }

// Update 3 of robot a never arrived: the map cannot take 4 and later, so they have no full-resend
// figure until a snapshot; the bytes that came in compressed are the message's.
TEST(Bandwidth, AGapLeavesUpdatesWithoutAFullResendFigure) {
  const std::vector<RobotUpdate>& stream = tiny().streams[0];
  BandwidthLedger ledger;
  for (const RobotUpdate& u : stream) {
    if (u.sequence != 3) ledger.add(u, 100);
  }
  RobotUpdate snapshot;
  {
    RobotStreamState map;
    for (const RobotUpdate& u : stream) ASSERT_TRUE(map.add(u).ok());
    snapshot = map.snapshot();  // of everything, with the last update's sequence
  }
  ledger.add(snapshot, 100);
  const std::vector<UpdateBandwidth> rows = ledger.rows();
  ASSERT_EQ(rows.size(), stream.size());
  const auto totals = bandwidthTotals(rows);
  EXPECT_EQ(totals.at(RobotId(0)).without_full_resend, stream.size() - 4);
  EXPECT_EQ(totals.at(RobotId(0)).wire_bytes, 100 * stream.size());
  EXPECT_TRUE(rows.back().snapshot);
  EXPECT_TRUE(rows.back().full_resend_bytes.has_value());  // the snapshot: the map again
  EXPECT_EQ(count(bandwidthSvg(rows), "<polyline class=\"wire\""), 1u);
}

}  // namespace
}  // namespace hydra_multi
