#include "hydra_multi/backend/round_memory.h"

#include <gtest/gtest.h>

namespace hydra_multi {
namespace {

Eigen::Isometry3d at(double x, double y, double yaw = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

// Robots 1 and 2; robot 1's keyframes 0 and 1 (t = 1, 2 s), robot 2's keyframe 0. The round's
// solves move each node by a motion of its own, which the next round must find again.
class RoundMemoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    addKeyframe(a0, 1);
    addKeyframe(a1, 2);
    addKeyframe(b0, 1);
    graph.skeleton.poses = {{a0, at(0, 0)}, {a1, at(5, 0)}, {b0, at(0, 3)}};
    graph.initial = graph.skeleton.poses;
    for (const auto& [id, initial] : graph.initial) {
      result.poses[id] = whole_motion.at(id) * initial;
      result.solve.poses[id] = skeleton_motion.at(id) * initial;
      proposal[id] = proposal_motion.at(id) * initial;
      held_out[id] = held_out_motion.at(id) * initial;
    }
    result.robust_inlier = {{{a1, b0}, true}, {{a0, b0}, false}};
    alignment = {{r1, at(0, 0)}, {r2, at(1, 2, 0.5)}};
  }

  void addKeyframe(NodeId id, int64_t seconds) {
    Node node = makeNode(id, Layer::kAgents);
    node.find<AgentAttributes>()->timestamp_ns = seconds * 1000000000;
    frontend.addOrUpdateNode(node);
  }

  // The next round's graph: robot 1's keyframe 2 (t = 3 s) new, the others where they were.
  DeformationGraph next() {
    addKeyframe(a2, 3);
    DeformationGraph later = graph;
    later.skeleton.poses[a2] = at(9, 1);
    later.initial = later.skeleton.poses;
    return later;
  }

  const RobotId r1{1}, r2{2};
  const NodeId a0 = NodeId::station(r1.prefix(), r1, 0), a1 = NodeId::station(r1.prefix(), r1, 1),
               a2 = NodeId::station(r1.prefix(), r1, 2), b0 = NodeId::station(r2.prefix(), r2, 0);
  const std::map<NodeId, Eigen::Isometry3d> whole_motion = {
      {a0, at(0.1, 0, 0.01)}, {a1, at(0.2, 0.1, 0.02)}, {b0, at(-0.3, 0, 0.03)}};
  const std::map<NodeId, Eigen::Isometry3d> skeleton_motion = {
      {a0, at(0.0, 0.1)}, {a1, at(0.4, 0.1)}, {b0, at(0.0, -0.2)}};
  const std::map<NodeId, Eigen::Isometry3d> proposal_motion = {
      {a0, at(0.5, 0)}, {a1, at(0.6, 0, 0.1)}, {b0, at(0.7, 0)}};
  const std::map<NodeId, Eigen::Isometry3d> held_out_motion = {
      {a0, at(0, 0.5)}, {a1, at(0, 0.6, -0.1)}, {b0, at(0, 0.7)}};
  SceneGraph frontend;
  DeformationGraph graph;
  DeformationResult result;
  std::map<NodeId, Eigen::Isometry3d> proposal, held_out;
  std::map<RobotId, Eigen::Isometry3d> alignment;
};

TEST_F(RoundMemoryTest, ANodeNewSinceMovesAsItsRobotsLatestKeyframe) {
  RoundMemory memory;
  memory.remember(frontend, graph, result, proposal, held_out, alignment, true);
  const DeformationGraph later = next();
  std::map<NodeId, Eigen::Isometry3d> last_proposal, last_held_out;
  const DeformationWarmStart warm =
      memory.lastRound(later, alignment, &last_proposal, &last_held_out);

  ASSERT_EQ(warm.poses.size(), 4u);
  for (const NodeId id : {a0, a1, b0}) {
    EXPECT_TRUE(warm.poses.at(id).isApprox(whole_motion.at(id) * later.initial.at(id), 1e-12));
    EXPECT_TRUE(warm.last_whole.at(id).isApprox(result.poses.at(id), 1e-12));
    EXPECT_TRUE(warm.last_skeleton.at(id).isApprox(result.solve.poses.at(id), 1e-12));
    EXPECT_TRUE(last_proposal.at(id).isApprox(proposal.at(id), 1e-12));
    EXPECT_TRUE(last_held_out.at(id).isApprox(held_out.at(id), 1e-12));
  }
  // Keyframe 2 is new: it moves as keyframe 1, robot 1's latest, moved in each solution.
  EXPECT_TRUE(warm.poses.at(a2).isApprox(whole_motion.at(a1) * later.initial.at(a2), 1e-12));
  EXPECT_TRUE(last_proposal.at(a2).isApprox(proposal_motion.at(a1) * later.initial.at(a2), 1e-12));
  EXPECT_TRUE(last_held_out.at(a2).isApprox(held_out_motion.at(a1) * later.initial.at(a2), 1e-12));
  // The earlier solutions hold only what they solved.
  EXPECT_EQ(warm.last_whole.count(a2), 0u);
  EXPECT_EQ(warm.last_skeleton.count(a2), 0u);
  EXPECT_EQ(warm.verdicts, result.robust_inlier);
}

TEST_F(RoundMemoryTest, ARobotAlignedOtherwiseTakesNothing) {
  RoundMemory memory;
  memory.remember(frontend, graph, result, proposal, held_out, alignment, true);
  std::map<RobotId, Eigen::Isometry3d> realigned = alignment;
  realigned[r2] = at(1, 2.5, 0.5);
  EXPECT_EQ(memory.alignedAsBefore(alignment), (std::set<RobotId>{r1, r2}));
  EXPECT_EQ(memory.alignedAsBefore(realigned), (std::set<RobotId>{r1}));

  std::map<NodeId, Eigen::Isometry3d> last_proposal, last_held_out;
  const DeformationWarmStart warm =
      memory.lastRound(graph, realigned, &last_proposal, &last_held_out);
  using Poses = std::map<NodeId, Eigen::Isometry3d>;
  for (const Poses* poses : std::vector<const Poses*>{
           &warm.poses, &warm.last_whole, &warm.last_skeleton, &last_proposal, &last_held_out}) {
    EXPECT_EQ(poses->count(a0), 1u);
    EXPECT_EQ(poses->count(b0), 0u);
  }
  // Both loop closures join robot 2: no verdict is taken.
  EXPECT_TRUE(warm.verdicts.empty());
}

TEST_F(RoundMemoryTest, WithoutPosesOnlyTheAlignmentIsKept) {
  RoundMemory memory;
  memory.remember(frontend, graph, result, proposal, held_out, alignment, true);
  // Kept: poses and verdicts.
  const DeformationWarmStart kept = memory.lastRound(graph, alignment);
  EXPECT_EQ(kept.poses.size(), 3u);
  EXPECT_EQ(kept.verdicts, result.robust_inlier);

  // A round that keeps no poses forgets the ones before it.
  memory.remember(frontend, graph, result, proposal, held_out, alignment, false);
  EXPECT_EQ(memory.alignedAsBefore(alignment), (std::set<RobotId>{r1, r2}));
  const DeformationWarmStart warm = memory.lastRound(graph, alignment);
  EXPECT_TRUE(warm.poses.empty());
  EXPECT_TRUE(warm.last_whole.empty());
  EXPECT_TRUE(warm.last_skeleton.empty());
  EXPECT_TRUE(warm.verdicts.empty());
}

}  // namespace
}  // namespace hydra_multi
