// Initial alignment from known transforms, with outlier loop closures among the inter-robot ones.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hydra_multi/backend/initial_alignment.h"
#include "hydra_multi/core/se3.h"

namespace hydra_multi {
namespace {

struct Team {
  SceneGraph frontend;
  std::map<RobotId, Eigen::Isometry3d> T_global_robot;      // the truth
  std::map<RobotId, std::vector<Eigen::Isometry3d>> truth;  // global poses of the keyframes
};

NodeId keyframeId(RobotId robot, size_t k) { return NodeId::station(robot.prefix(), robot, k); }

// Robots driving the same loop of 40 keyframes in the global frame, each recorded in its own
// frame (its first pose), shifted along the loop so that they start at different places.
Team team(size_t robots) {
  Team t;
  for (size_t r = 0; r < robots; ++r) {
    const RobotId robot(static_cast<uint8_t>(r));
    std::vector<Eigen::Isometry3d> global;
    for (size_t k = 0; k < 40; ++k) {
      const double angle = 2.0 * M_PI * double(k + 10 * r) / 40.0;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() << 10.0 * std::cos(angle), 10.0 * std::sin(angle), 0.0;
      T.linear() = Eigen::AngleAxisd(angle + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      global.push_back(T);
    }
    t.T_global_robot[robot] = global.front();
    for (size_t k = 0; k < global.size(); ++k) {
      const Eigen::Isometry3d local = global.front().inverse() * global[k];
      Node node = makeNode(keyframeId(robot, k), Layer::kAgents, local.translation());
      node.find<AgentAttributes>()->orientation = Eigen::Quaterniond(local.linear());
      node.find<AgentAttributes>()->timestamp_ns = static_cast<int64_t>(k) * 1000000000;
      t.frontend.addOrUpdateNode(node);
    }
    t.truth[robot] = global;
  }
  return t;
}

// `good` true loop closures between robots a and b (same global pose, noisy) and `bad` wrong ones.
std::vector<PoseGraphEdge> closures(const Team& t, RobotId a, RobotId b, size_t good, size_t bad,
                                    uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, 39);
  std::normal_distribution<double> noise(0.0, 0.02), rotation(0.0, 0.005), unit(0.0, 1.0);
  std::vector<PoseGraphEdge> edges;
  for (size_t i = 0; i < good + bad; ++i) {
    PoseGraphEdge e;
    e.kind = PoseGraphEdge::Kind::kLoopClosure;
    const size_t ka = pick(rng), kb = pick(rng);
    e.from = keyframeId(a, ka);
    e.to = keyframeId(b, kb);
    e.T_from_to = t.truth.at(a)[ka].inverse() * t.truth.at(b)[kb];
    Vector6d xi;
    xi << noise(rng), noise(rng), noise(rng), rotation(rng), rotation(rng), rotation(rng);
    if (i >= good) {  // 4-8 m and 30-90 degrees off, in a random direction
      const double angle = 2 * M_PI * std::abs(unit(rng)),
                   metres = 4.0 + std::fmod(std::abs(4 * unit(rng)), 4.0);
      xi << metres * std::cos(angle), metres * std::sin(angle), 0, 0, 0,
          (unit(rng) < 0 ? -1 : 1) * (0.5 + std::fmod(std::abs(unit(rng)), 1.0));
    }
    e.T_from_to = e.T_from_to * expSE3(xi);
    edges.push_back(e);
  }
  return edges;
}

TEST(InitialAlignment, KnownTransformsDespiteOutliers) {
  const Team t = team(3);
  const RobotId a(0), b(1), c(2);
  std::vector<PoseGraphEdge> edges = closures(t, a, b, 12, 20, 1);
  const auto bc = closures(t, b, c, 10, 10, 2);
  edges.insert(edges.end(), bc.begin(), bc.end());
  InitialAlignment alignment;
  const auto& aligned = alignment.update(t.frontend, edges, a);
  ASSERT_EQ(aligned.size(), 3u);
  for (const auto& [robot, frame] : aligned) {
    // Relative to robot a's frame, the global frame of this test.
    const Eigen::Isometry3d expected =
        t.T_global_robot.at(a).inverse() * t.T_global_robot.at(robot);
    EXPECT_LT((frame.T_global_robot.translation() - expected.translation()).norm(), 0.1)
        << robot.str();
    EXPECT_LT(
        Eigen::AngleAxisd(frame.T_global_robot.linear().transpose() * expected.linear()).angle(),
        0.02);
  }
  EXPECT_GE(aligned.at(b).inliers, 10u);
}

// A robot with fewer than k = 5 agreeing loop closures stays in its own frame.
TEST(InitialAlignment, TooFewInliersStaysUnaligned) {
  const Team t = team(2);
  InitialAlignment alignment;
  const auto& aligned =
      alignment.update(t.frontend, closures(t, RobotId(0), RobotId(1), 4, 6, 3), RobotId(0));
  EXPECT_TRUE(alignment.isAligned(RobotId(0)));
  EXPECT_FALSE(alignment.isAligned(RobotId(1)));
  EXPECT_EQ(aligned.size(), 1u);
}

// Once aligned, a robot keeps its alignment unless the optimized result moves its start by more
// than 10 m.
TEST(InitialAlignment, RealignsOnlyOnLargeDisagreement) {
  const Team t = team(2);
  const RobotId a(0), b(1);
  InitialAlignment alignment;
  alignment.update(t.frontend, closures(t, a, b, 10, 0, 4), a);
  const Eigen::Isometry3d first = alignment.aligned().at(b).T_global_robot;
  // The optimizer agrees within 3 m: kept, even though new loop closures would say otherwise.
  Eigen::Isometry3d near = first;
  near.translation().x() += 3.0;
  alignment.update(t.frontend, closures(t, a, b, 10, 0, 5), a, {{b, near}});
  EXPECT_EQ(alignment.realignments(), 0u);
  EXPECT_TRUE(alignment.aligned().at(b).T_global_robot.isApprox(first));
  Eigen::Isometry3d far = first;
  far.translation().x() += 15.0;
  alignment.update(t.frontend, closures(t, a, b, 10, 0, 6), a, {{b, far}});
  EXPECT_EQ(alignment.realignments(), 1u);
}

// With realign_against_verdicts (the default), a robot whose optimized start lies far from the
// estimate's is re-aligned only where the optimization rejected the loop closures the estimate
// holds: a map that keeps them (a start moved by drift) keeps its frame; one that rejected them, or
// decided none of them, is re-aligned; without the option the distance alone decides.
TEST(InitialAlignment, RealignsAgainstTheOptimizationsVerdicts) {
  const Team t = team(2);
  const RobotId a(0), b(1);
  const auto edges = closures(t, a, b, 10, 0, 4);
  const auto verdicts = [&](bool kept) {
    std::map<std::pair<NodeId, NodeId>, bool> v;
    for (const PoseGraphEdge& e : edges) v[{e.from, e.to}] = kept;
    return v;
  };
  const std::map<std::pair<NodeId, NodeId>, bool> all_kept = verdicts(true),
                                                  all_rejected = verdicts(false), none;
  InitialAlignmentOptions options, distance_alone;
  distance_alone.realign_against_verdicts = false;
  const auto realigned = [&](const InitialAlignmentOptions& o,
                             const std::map<std::pair<NodeId, NodeId>, bool>& given) {
    InitialAlignment alignment(o);
    alignment.update(t.frontend, edges, a);
    Eigen::Isometry3d far = alignment.aligned().at(b).T_global_robot;
    far.translation().x() += 15.0;
    alignment.update(t.frontend, edges, a, {{b, far}}, {}, false, &given);
    EXPECT_EQ(alignment.realignments() + alignment.realignmentsAgreed(), 1u);
    return alignment.realignments() == 1;
  };
  EXPECT_FALSE(realigned(options, all_kept));
  EXPECT_TRUE(realigned(options, all_rejected));
  EXPECT_TRUE(realigned(options, none));
  EXPECT_TRUE(realigned(distance_alone, all_kept));
  // Below the share: three of ten rejected, against the default half.
  std::map<std::pair<NodeId, NodeId>, bool> three_of_ten = all_kept;
  size_t k = 0;
  for (auto& [edge, kept] : three_of_ten) kept = k++ % 4 != 0;
  EXPECT_FALSE(realigned(options, three_of_ten));
  options.realign_rejected_share = 0.2;
  EXPECT_TRUE(realigned(options, three_of_ten));
}

// A round afresh takes this round's estimate, whatever the optimized result says, and counts no
// re-alignment; the next ordinary round keeps it.
TEST(InitialAlignment, ARoundAfreshTakesTheEstimate) {
  const Team t = team(2);
  const RobotId a(0), b(1);
  InitialAlignment alignment, once;
  alignment.update(t.frontend, closures(t, a, b, 10, 0, 4), a);
  const Eigen::Isometry3d first = alignment.aligned().at(b).T_global_robot;
  const auto later = closures(t, a, b, 10, 0, 5);
  alignment.update(t.frontend, later, a, {{b, first}});
  EXPECT_TRUE(alignment.aligned().at(b).T_global_robot.isApprox(first));  // kept
  alignment.update(t.frontend, later, a, {{b, first}}, {}, true);
  once.update(t.frontend, later, a);
  const Eigen::Isometry3d& afresh = alignment.aligned().at(b).T_global_robot;
  EXPECT_FALSE(afresh.isApprox(first));
  EXPECT_TRUE(afresh.isApprox(once.aligned().at(b).T_global_robot));
  EXPECT_EQ(alignment.realignments(), 0u);
  alignment.update(t.frontend, closures(t, a, b, 10, 0, 6), a, {{b, afresh}});
  EXPECT_TRUE(alignment.aligned().at(b).T_global_robot.isApprox(afresh));
}

// Look-alike rooms: loop closures that all agree on robot b sitting 15 m off along x.
std::vector<PoseGraphEdge> shiftedClosures(const Team& t, RobotId a, RobotId b, size_t count,
                                           uint64_t seed) {
  Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
  shift.translation().x() = 15.0;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, 39);
  std::vector<PoseGraphEdge> edges;
  for (size_t i = 0; i < count; ++i) {
    PoseGraphEdge e;
    e.kind = PoseGraphEdge::Kind::kLoopClosure;
    const size_t ka = pick(rng), kb = pick(rng);
    e.from = keyframeId(a, ka);
    e.to = keyframeId(b, kb);
    e.T_from_to = t.truth.at(a)[ka].inverse() * shift * t.truth.at(b)[kb];
    edges.push_back(e);
  }
  return edges;
}

// A wrong early alignment (the look-alike cluster was the largest) is replaced once the loop
// closures found since say otherwise and the optimized result, which started from the wrong
// alignment and stayed there, is more than 10 m from the new estimate.
TEST(InitialAlignment, ReplacesAWrongEarlyAlignment) {
  const Team t = team(2);
  const RobotId a(0), b(1);
  InitialAlignment alignment;
  std::vector<PoseGraphEdge> edges = shiftedClosures(t, a, b, 8, 7);
  const auto early_good = closures(t, a, b, 3, 0, 8);
  edges.insert(edges.end(), early_good.begin(), early_good.end());
  alignment.update(t.frontend, edges, a);
  const Eigen::Isometry3d expected = t.T_global_robot.at(a).inverse() * t.T_global_robot.at(b);
  const Eigen::Isometry3d wrong = alignment.aligned().at(b).T_global_robot;
  ASSERT_GT((wrong.translation() - expected.translation()).norm(), 10.0);
  // The optimization kept the wrong frame; by now the right loop closures are the majority.
  const auto later_good = closures(t, a, b, 20, 0, 9);
  edges.insert(edges.end(), later_good.begin(), later_good.end());
  alignment.update(t.frontend, edges, a, {{b, wrong}});
  EXPECT_EQ(alignment.realignments(), 1u);
  EXPECT_LT(
      (alignment.aligned().at(b).T_global_robot.translation() - expected.translation()).norm(),
      0.1);
}

// Look-alike loop closures come to outnumber the right ones: the estimate puts robot b 15 m off,
// the robot is re-aligned to it, and the optimization, started there, puts b's start back where
// it was. That estimate is refuted: b is not re-aligned to it again while the optimized start
// is there; once the optimized start moves, it is tried again. Without decline_refuted it is
// taken every round.
TEST(InitialAlignment, DeclinesAnEstimateTheOptimizationRefuted) {
  const Team t = team(2);
  const RobotId a(0), b(1);
  const Eigen::Isometry3d right = t.T_global_robot.at(a).inverse() * t.T_global_robot.at(b);
  std::vector<PoseGraphEdge> edges = closures(t, a, b, 10, 0, 10);
  InitialAlignmentOptions plain;
  plain.decline_refuted = false;
  InitialAlignment alignment, every_time(plain);
  alignment.update(t.frontend, edges, a);
  every_time.update(t.frontend, edges, a);
  const auto look_alikes = shiftedClosures(t, a, b, 30, 11);
  edges.insert(edges.end(), look_alikes.begin(), look_alikes.end());
  const auto startOf = [b](const InitialAlignment& x) {
    return Eigen::Vector3d(x.aligned().at(b).T_global_robot.translation());
  };
  for (int round = 0; round < 3; ++round) {
    alignment.update(t.frontend, edges, a, {{b, right}});
    every_time.update(t.frontend, edges, a, {{b, right}});
    EXPECT_GT((startOf(alignment) - right.translation()).norm(), 10.0);  // the estimate's frame
  }
  EXPECT_EQ(alignment.realignments(), 1u);
  EXPECT_EQ(alignment.realignmentsDeclined(), 2u);
  EXPECT_EQ(every_time.realignments(), 3u);
  EXPECT_EQ(every_time.realignmentsDeclined(), 0u);
  // The optimized start moved by 3 m (within 10 m of the estimate's still): tried again.
  Eigen::Isometry3d moved = right;
  moved.translation().y() += 3.0;
  alignment.update(t.frontend, edges, a, {{b, moved}});
  EXPECT_EQ(alignment.realignments(), 2u);
  EXPECT_EQ(alignment.realignmentsDeclined(), 2u);
  // A round where the optimized start agrees with the estimate keeps the refutation: back where
  // it was refuted, the estimate is declined again.
  alignment.update(t.frontend, edges, a, {{b, alignment.aligned().at(b).T_global_robot}});
  alignment.update(t.frontend, edges, a, {{b, moved}});
  EXPECT_EQ(alignment.realignments(), 2u);
  EXPECT_EQ(alignment.realignmentsDeclined(), 3u);
}

// The spanning tree composes robot c's estimate through the pair (b, c), whose look-alike loop
// closures (32) have come to outnumber its right ones (15) and the pair (a, c)'s (30): the
// estimate puts c 15 m off. In that frame 32 of c's loop closures fit, in its kept frame 45, so c
// keeps its frame (realign_fit_share). Without the check (0) it is re-aligned.
TEST(InitialAlignment, DeclinesAnEstimateThatFitsFewerLoopClosures) {
  const Team t = team(3);
  const RobotId a(0), b(1), c(2);
  std::vector<PoseGraphEdge> edges = closures(t, a, b, 50, 0, 20);
  for (const auto& more : {closures(t, a, c, 30, 0, 21), closures(t, b, c, 15, 0, 22)})
    edges.insert(edges.end(), more.begin(), more.end());
  InitialAlignmentOptions unchecked;
  unchecked.realign_fit_share = 0.0;
  InitialAlignment alignment, every_time(unchecked);
  alignment.update(t.frontend, edges, a);
  every_time.update(t.frontend, edges, a);
  const Eigen::Isometry3d right = t.T_global_robot.at(a).inverse() * t.T_global_robot.at(c);
  const auto offRight = [&](const InitialAlignment& x) {
    return (x.aligned().at(c).T_global_robot.translation() - right.translation()).norm();
  };
  ASSERT_LT(offRight(alignment), 0.1);
  const auto look_alikes = shiftedClosures(t, b, c, 32, 23);
  edges.insert(edges.end(), look_alikes.begin(), look_alikes.end());
  const std::map<RobotId, Eigen::Isometry3d> optimized = {
      {b, alignment.aligned().at(b).T_global_robot}, {c, right}};
  alignment.update(t.frontend, edges, a, optimized);
  every_time.update(t.frontend, edges, a, optimized);
  EXPECT_EQ(alignment.realignments(), 0u);
  EXPECT_EQ(alignment.realignmentsUnfit(), 1u);
  EXPECT_LT(offRight(alignment), 0.1);
  EXPECT_EQ(every_time.realignments(), 1u);
  EXPECT_EQ(every_time.realignmentsUnfit(), 0u);
  EXPECT_GT(offRight(every_time), 10.0);
}

// The fit is weighed as the consensus weighs: robot b, aligned to 10 look-alikes while they
// weighed most, is re-aligned once two distinctive right loop closures outweigh them, although
// in the right frame 6 loop closures fit against 10 in the kept one.
TEST(InitialAlignment, WeighsTheFitOfAnEstimateBySupport) {
  const Team t = team(2);
  const RobotId a(0), b(1);
  std::vector<PoseGraphEdge> edges = shiftedClosures(t, a, b, 10, 24);
  const auto good = closures(t, a, b, 6, 0, 25);
  edges.insert(edges.end(), good.begin(), good.end());
  std::vector<double> early(10, 1.0), later(10, 0.5);
  for (size_t i = 0; i < good.size(); ++i) {
    early.push_back(0.1);
    later.push_back(i < 2 ? 3.0 : 0.5);
  }
  InitialAlignment alignment;
  alignment.update(t.frontend, edges, a, {}, early);
  const Eigen::Isometry3d right = t.T_global_robot.at(a).inverse() * t.T_global_robot.at(b);
  const Eigen::Isometry3d wrong = alignment.aligned().at(b).T_global_robot;
  ASSERT_GT((wrong.translation() - right.translation()).norm(), 10.0);
  alignment.update(t.frontend, edges, a, {{b, wrong}}, later);
  EXPECT_EQ(alignment.realignments(), 1u);
  EXPECT_EQ(alignment.realignmentsUnfit(), 0u);
  EXPECT_LT((alignment.aligned().at(b).T_global_robot.translation() - right.translation()).norm(),
            0.1);
}

// Support per loop closure: 6 right ones, two of them distinctive, against 10 look-alikes that
// agree on a wrong frame. Weighed, the right frame wins; by count (weigh_support off), the wrong.
TEST(InitialAlignment, WeighsLoopClosuresBySupport) {
  const Team t = team(2);
  const RobotId a(0), b(1);
  std::vector<PoseGraphEdge> edges = shiftedClosures(t, a, b, 10, 10);
  std::vector<double> support(edges.size(), 0.0);
  const auto good = closures(t, a, b, 6, 0, 11);
  edges.insert(edges.end(), good.begin(), good.end());
  for (size_t i = 0; i < good.size(); ++i) support.push_back(i < 2 ? 3.0 : 0.0);
  const Eigen::Isometry3d expected = t.T_global_robot.at(a).inverse() * t.T_global_robot.at(b);
  InitialAlignment weighed;
  weighed.update(t.frontend, edges, a, {}, support);
  ASSERT_TRUE(weighed.isAligned(b));
  EXPECT_LT((weighed.aligned().at(b).T_global_robot.translation() - expected.translation()).norm(),
            0.1);
  InitialAlignmentOptions by_count;
  by_count.weigh_support = false;
  InitialAlignment counted(by_count);
  counted.update(t.frontend, edges, a, {}, support);
  ASSERT_TRUE(counted.isAligned(b));
  EXPECT_GT((counted.aligned().at(b).T_global_robot.translation() - expected.translation()).norm(),
            10.0);
}

}  // namespace
}  // namespace hydra_multi
