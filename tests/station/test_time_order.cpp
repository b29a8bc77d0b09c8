// The time order: whatever order robots' updates arrive in, they leave in robot time (then robot,
// then sequence), as the file replay orders them; a robot that has nothing held holds the others
// back until it has, finishes, or the hold runs out; the team is complete only once the expected
// robots have been heard of; what comes after later updates went on is counted late.

#include <gtest/gtest.h>

#include "hydra_multi/station/time_order.h"

namespace hydra_multi {
namespace {

using namespace std::chrono_literals;
using Clock = TimeOrder::Clock;

RobotUpdate at(uint8_t robot, uint64_t sequence, int64_t time_s) {
  RobotUpdate u;
  u.robot = RobotId(robot);
  u.sequence = sequence;
  u.time_ns = time_s * 1'000'000'000;
  return u;
}

std::vector<std::pair<uint8_t, uint64_t>> ids(const std::vector<RobotUpdate>& updates) {
  std::vector<std::pair<uint8_t, uint64_t>> out;
  for (const RobotUpdate& u : updates) out.emplace_back(u.robot.index(), u.sequence);
  return out;
}

TEST(TimeOrder, ReleasesInRobotTimeOnceEveryRobotHasSomethingHeld) {
  const Clock::time_point t0 = Clock::now();
  TimeOrder order(10s, 2);
  order.add(at(0, 0, 5), t0);
  order.add(at(0, 1, 10), t0);
  order.add(at(0, 2, 15), t0);
  EXPECT_TRUE(order.release(t0).empty());  // robot b not heard of: the team is not complete
  order.add(at(1, 0, 7), t0);
  // a0 (5 s) goes: b has a later one held; b0 (7 s) waits, for a has 10 s held... then a1 (10 s)
  // waits for b, which has nothing held.
  EXPECT_EQ(ids(order.release(t0)), (std::vector<std::pair<uint8_t, uint64_t>>{{0, 0}, {1, 0}}));
  order.add(at(1, 1, 10), t0);  // a tie in time: robot a first; a2 (15 s) then waits for b
  EXPECT_EQ(ids(order.release(t0)), (std::vector<std::pair<uint8_t, uint64_t>>{{0, 1}, {1, 1}}));
  EXPECT_TRUE(order.release(t0).empty());
  order.finish(RobotId(1));  // b said BYE: nobody to wait for
  EXPECT_EQ(ids(order.release(t0)), (std::vector<std::pair<uint8_t, uint64_t>>{{0, 2}}));
  EXPECT_EQ(order.held(), 0u);
  EXPECT_FALSE(order.deadline().has_value());
}

TEST(TimeOrder, NoneWaitsLongerThanTheHold) {
  const Clock::time_point t0 = Clock::now();
  TimeOrder order(2s);
  order.add(at(1, 0, 1), t0);
  order.add(at(0, 0, 3), t0 + 1s);
  order.add(at(0, 1, 8), t0 + 1s);
  // b0 (1 s) goes at once: a has later ones held. a0 waits for b, which has nothing held.
  EXPECT_EQ(ids(order.release(t0 + 1s)), (std::vector<std::pair<uint8_t, uint64_t>>{{1, 0}}));
  ASSERT_TRUE(order.deadline().has_value());
  EXPECT_EQ(*order.deadline(), t0 + 3s);
  EXPECT_TRUE(order.release(t0 + 2s).empty());
  // b silent: at the hold a0 goes, and a1, which arrived with it.
  EXPECT_EQ(ids(order.release(t0 + 3s)),
            (std::vector<std::pair<uint8_t, uint64_t>>{{0, 0}, {0, 1}}));
  order.add(at(1, 1, 9), t0 + 4s);
  EXPECT_EQ(ids(order.release(t0 + 4s, true)),
            (std::vector<std::pair<uint8_t, uint64_t>>{{1, 1}}));  // everything, at the end
}

TEST(TimeOrder, AnUpdateAfterLaterOnesWentOnIsLate) {
  const Clock::time_point t0 = Clock::now();
  TimeOrder order(2s, 2);
  order.add(at(0, 0, 1), t0);
  order.add(at(1, 0, 2), t0);
  order.add(at(0, 1, 5), t0);
  // a0, b0 in time; a1 (5 s) waits for b until the hold runs out.
  EXPECT_EQ(ids(order.release(t0)), (std::vector<std::pair<uint8_t, uint64_t>>{{0, 0}, {1, 0}}));
  EXPECT_EQ(ids(order.release(t0 + 2s)), (std::vector<std::pair<uint8_t, uint64_t>>{{0, 1}}));
  EXPECT_TRUE(order.late().empty());
  // b1 (4 s) comes after a1 (5 s) went on: late; b2 (6 s) is in time again.
  order.add(at(1, 1, 4), t0 + 3s);
  order.add(at(1, 2, 6), t0 + 3s);
  order.finish(RobotId(0));
  EXPECT_EQ(ids(order.release(t0 + 3s)),
            (std::vector<std::pair<uint8_t, uint64_t>>{{1, 1}, {1, 2}}));
  EXPECT_EQ(order.late(), (std::map<RobotId, size_t>{{RobotId(1), 1}}));
}

}  // namespace
}  // namespace hydra_multi
