#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/core/node_id.h"

namespace hydra_multi {
namespace {

// The layout matches GTSAM symbols / Hydra ids: category in the top byte, index below.
TEST(NodeId, RobotSideLayoutMatchesGtsamSymbols) {
  const NodeId id('p', 6);
  EXPECT_EQ(id.value(), 8070450532247928838ULL);  // a place id from apartment_dsg.json
  EXPECT_EQ(id.category(), 'p');
  EXPECT_EQ(id.index(), 6u);
  EXPECT_FALSE(id.isStation());
  EXPECT_FALSE(id.sourceRobot().has_value());
}

TEST(NodeId, ReadableForms) {
  EXPECT_EQ(NodeId('O', 3).str(), "O(3)");
  EXPECT_EQ(NodeId('p', 17).str(), "p(17)");
  EXPECT_EQ(NodeId('a', 12).str(), "a12");
  EXPECT_EQ(NodeId::station('O', RobotId(1), 3).str(), "O(3)@b");
  EXPECT_EQ(NodeId(static_cast<char>(200), 3).str(), "#200(3)");
}

// Station ids keep category, robot and index apart, and collide neither with each other nor with
// robot-side ids.
TEST(NodeId, StationIdsNameTheirRobot) {
  const NodeId a = NodeId::station('O', RobotId(0), 42);
  const NodeId b = NodeId::station('O', RobotId(2), 42);
  EXPECT_NE(a, b);
  EXPECT_NE(a, NodeId('O', 42));
  EXPECT_EQ(a.category(), 'O');
  EXPECT_EQ(a.index(), 42u);
  EXPECT_EQ(b.sourceRobot(), RobotId(2));
  EXPECT_THROW(NodeId::station('O', RobotId(0), NodeId::kMaxStationIndex + 1), std::out_of_range);
  EXPECT_THROW(NodeId('O', NodeId::kMaxRobotIndex + 1), std::out_of_range);
}

// str() and parse() are inverse on random ids of every kind.
TEST(NodeId, ParseInvertsStr) {
  std::mt19937_64 rng(3);
  const std::string categories = "OpRBabcqz";
  for (int i = 0; i < 2000; ++i) {
    const char c = categories[rng() % categories.size()];
    const NodeId id = (i % 2 == 0) ? NodeId(c, rng() % NodeId::kMaxRobotIndex)
                                   : NodeId::station(c, RobotId(static_cast<uint8_t>(rng() % 25)),
                                                     rng() % NodeId::kMaxStationIndex);
    const auto parsed = NodeId::parse(id.str());
    ASSERT_TRUE(parsed.has_value()) << id.str();
    EXPECT_EQ(*parsed, id) << id.str();
  }
  EXPECT_EQ(NodeId::parse("#200(3)"), NodeId(static_cast<char>(200), 3));
}

TEST(NodeId, ParseRejectsMalformedText) {
  for (const char* text :
       {"", "O", "O(", "O()", "O(3", "O(x)", "a", "a(3)", "p12", "O(3)@", "O(3)@p", "O(3)@ab",
        "#65(3)", "#999(1)", "O(99999999999999999999999)", "O(3)x"}) {
    EXPECT_FALSE(NodeId::parse(text).has_value()) << text;
  }
}

// Robot letters skip 'p' (places), and prefix/fromPrefix are inverse over all robots.
TEST(RobotId, PrefixLettersSkipPlaces) {
  EXPECT_EQ(RobotId(0).prefix(), 'a');
  EXPECT_EQ(RobotId(14).prefix(), 'o');
  EXPECT_EQ(RobotId(15).prefix(), 'q');
  EXPECT_EQ(RobotId(24).prefix(), 'z');
  EXPECT_FALSE(RobotId::fromPrefix('p').has_value());
  EXPECT_FALSE(RobotId::fromPrefix('A').has_value());
  for (uint8_t i = 0; i < RobotId::kMaxRobots; ++i) {
    EXPECT_EQ(RobotId::fromPrefix(RobotId(i).prefix()), RobotId(i));
  }
  EXPECT_FALSE(RobotId(25).isValid());
}

}  // namespace
}  // namespace hydra_multi
