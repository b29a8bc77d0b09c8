#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/multi_robot_alignment.h"
#include "hydra_multi/optim/outlier_injection.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

// Three robots with known frames: eq. (1)-(2) recover each robot's frame from loop closures of
// which 60 % are wrong, and a robot with fewer than k agreeing loop closures stays unaligned.
TEST(MultiRobotAlignment, RecoversFramesAmongOutliers) {
  std::mt19937 rng(111);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const std::vector<Eigen::Isometry3d> T_world_robot = {
      Eigen::Isometry3d::Identity(), expSE3((Vector6d() << 10, -3, 0.5, 0, 0, 1.0).finished()),
      expSE3((Vector6d() << -4, 8, 0, 0.05, 0, -2.0).finished())};
  std::map<NodeId, Eigen::Isometry3d> local, world;
  std::unordered_map<NodeId, size_t> robot_of;
  for (size_t r = 0; r < 3; ++r) {
    for (uint64_t i = 0; i < 30; ++i) {
      const NodeId id(RobotId(static_cast<uint8_t>(r)).prefix(), i);
      world[id] = expSE3((Vector6d() << 0.5 * i, std::sin(0.2 * i), 0, 0, 0, 0.1 * i).finished());
      local[id] = T_world_robot[r].inverse() * world[id];
      robot_of[id] = r;
    }
  }
  std::vector<PoseGraphEdge> edges;
  std::vector<bool> truth;
  for (size_t k = 0; k < 40; ++k) {
    const size_t ra = 0, rb = 1 + k % 2;
    const NodeId a(RobotId(static_cast<uint8_t>(ra)).prefix(), (k * 7) % 30);
    const NodeId b(RobotId(static_cast<uint8_t>(rb)).prefix(), (k * 11) % 30);
    PoseGraphEdge e;
    e.from = a;
    e.to = b;
    e.kind = PoseGraphEdge::Kind::kLoopClosure;
    const bool inlier = k % 5 < 2;  // 40 % inliers
    Vector6d noise;
    for (int i = 0; i < 6; ++i) noise[i] = (inlier ? 0.01 : 2.0) * gauss(rng);
    e.T_from_to = world[a].inverse() * world[b] * expSE3(noise);
    edges.push_back(e);
    truth.push_back(inlier);
  }
  const MultiRobotAlignment alignment = alignRobotFrames(3, local, robot_of, edges);
  ASSERT_EQ(alignment.numAligned(), 3u);
  for (size_t r = 0; r < 3; ++r) {
    EXPECT_LT(logSE3(relativePose(T_world_robot[r], *alignment.T_world_robot[r])).norm(), 0.05)
        << r;
  }
  EXPECT_EQ(alignment.edge_inlier, truth);

  MultiRobotAlignmentOptions strict;
  strict.min_inliers = 9;  // each pair has 8 inliers
  EXPECT_EQ(alignRobotFrames(3, local, robot_of, edges, 0, strict).numAligned(), 1u);

  // The pairs averaged on one thread, on two (one pair each) and on more threads than pairs, with
  // and without consensus caches: the same alignment to the bit.
  for (const size_t threads : {1u, 2u, 5u}) {
    MultiRobotAlignmentOptions options;
    options.threads = threads;
    std::map<std::pair<size_t, size_t>, ConsensusCache> caches;
    for (auto* cache : {static_cast<decltype(caches)*>(nullptr), &caches, &caches}) {
      const MultiRobotAlignment again =
          alignRobotFrames(3, local, robot_of, edges, 0, options, {}, cache);
      EXPECT_EQ(again.edge_inlier, alignment.edge_inlier);
      ASSERT_EQ(again.pairs.size(), alignment.pairs.size());
      for (size_t p = 0; p < again.pairs.size(); ++p) {
        EXPECT_EQ(again.pairs[p].T_a_b.matrix(), alignment.pairs[p].T_a_b.matrix());
        EXPECT_EQ(again.pairs[p].inliers, alignment.pairs[p].inliers);
      }
      for (size_t r = 0; r < 3; ++r)
        EXPECT_EQ(again.T_world_robot[r]->matrix(), alignment.T_world_robot[r]->matrix());
    }
  }
}

// A loop closure the frontend finds again (the same two keyframes) is no new evidence: eight
// copies of one wrong match do not align a robot, while five loop closures between distinct
// keyframes do, and the pair reports its distinct keyframe pairs as its inliers.
TEST(MultiRobotAlignment, OneMatchFoundAgainCountsOnce) {
  const Eigen::Isometry3d T_world_b = expSE3((Vector6d() << 6, 2, 0, 0, 0, 0.7).finished());
  std::map<NodeId, Eigen::Isometry3d> local, world;
  std::unordered_map<NodeId, size_t> robot_of;
  for (size_t r = 0; r < 2; ++r) {
    for (uint64_t i = 0; i < 10; ++i) {
      const NodeId id(RobotId(static_cast<uint8_t>(r)).prefix(), i);
      world[id] = expSE3((Vector6d() << i, 0.3 * i, 0, 0, 0, 0.05 * i).finished());
      local[id] = (r == 0 ? Eigen::Isometry3d::Identity() : T_world_b.inverse()) * world[id];
      robot_of[id] = r;
    }
  }
  const auto closure = [&](uint64_t i, uint64_t j, const Eigen::Isometry3d& error) {
    PoseGraphEdge e;
    e.from = NodeId(RobotId(0).prefix(), i);
    e.to = NodeId(RobotId(1).prefix(), j);
    e.kind = PoseGraphEdge::Kind::kLoopClosure;
    e.T_from_to = world[e.from].inverse() * world[e.to] * error;
    return e;
  };
  // A look-alike room: one wrong match (12 m off, turned 170 degrees), found eight times.
  const Eigen::Isometry3d wrong = expSE3((Vector6d() << 12, 0, 0, 0, 0, 2.97).finished());
  const std::vector<PoseGraphEdge> copies(8, closure(3, 7, wrong));
  const MultiRobotAlignment once = alignRobotFrames(2, local, robot_of, copies);
  EXPECT_EQ(once.numAligned(), 1u);
  ASSERT_EQ(once.pairs.size(), 1u);
  EXPECT_EQ(once.pairs[0].loop_closures, 8u);
  EXPECT_EQ(once.pairs[0].inliers, 1u);

  std::vector<PoseGraphEdge> distinct;
  for (uint64_t i = 0; i < 5; ++i)
    distinct.push_back(closure(i, i + 2, Eigen::Isometry3d::Identity()));
  const MultiRobotAlignment aligned = alignRobotFrames(2, local, robot_of, distinct);
  ASSERT_EQ(aligned.numAligned(), 2u);
  EXPECT_EQ(aligned.pairs[0].inliers, 5u);
  EXPECT_LT(logSE3(relativePose(T_world_b, *aligned.T_world_robot[1])).norm(), 1e-6);
}

// Injected outliers make up the requested share of loop closures, join non-consecutive poses,
// and are the same for the same seed.
TEST(OutlierInjection, ShareAndDeterminism) {
  auto file = io::readG2o(testing::dataDir() + "/pgo/smallGrid3D.g2o");
  ASSERT_TRUE(file.ok()) << file.error();
  PoseGraph g = file.value().graph;
  classifyEdges(g);
  const size_t loop_closures = g.numLoopClosures();
  PoseGraph a = g, b = g, c = g;
  const size_t n = injectOutliers(a, g.poses, 0.7, 5);
  injectOutliers(b, g.poses, 0.7, 5);
  injectOutliers(c, g.poses, 0.7, 6);
  EXPECT_NEAR(double(n) / double(loop_closures + n), 0.7, 0.01);
  ASSERT_EQ(a.edges.size(), g.edges.size() + n);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_NE(a.edges, c.edges);
  for (size_t k = g.edges.size(); k < a.edges.size(); ++k) {
    const PoseGraphEdge& e = a.edges[k];
    EXPECT_EQ(e.kind, PoseGraphEdge::Kind::kLoopClosure);
    EXPECT_GT(std::max(e.from.index(), e.to.index()) - std::min(e.from.index(), e.to.index()), 1u);
    EXPECT_NEAR(Eigen::Matrix3d(e.T_from_to.linear()).determinant(), 1.0, 1e-9);
  }
}

// Files merge with shared edges counted once; an edge between nodes of two files is a loop
// closure, whatever its ids.
TEST(MergeG2o, DeduplicatesAndClassifiesAcrossFiles) {
  const std::string dir = testing::dataDir() + "/multirobot/grid3d_2robots/";
  auto merged = io::readAndMergeG2o({dir + "0.g2o", dir + "1.g2o"});
  ASSERT_TRUE(merged.ok()) << merged.error();
  EXPECT_EQ(merged.value().graph.poses.size(), 16u);
  EXPECT_EQ(merged.value().graph.edges.size(), 28u);  // 16 + 16, 4 shared
  EXPECT_EQ(merged.value().duplicate_edges, 4u);
  for (const PoseGraphEdge& e : merged.value().graph.edges) {
    if (e.from.category() != e.to.category()) {
      EXPECT_EQ(e.kind, PoseGraphEdge::Kind::kLoopClosure);
    }
  }
  EXPECT_EQ(merged.value().node_owner.at(NodeId('b', 2)), 1u);
}

}  // namespace
}  // namespace hydra_multi
