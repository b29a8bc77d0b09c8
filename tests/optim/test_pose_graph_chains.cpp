#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/core/se3.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/pose_graph_chains.h"
#include "hydra_multi/optim/pose_graph_optimizer.h"
#include "hydra_multi/optim/robust_pose_graph.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

Eigen::Isometry3d randomStep(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 0.3);
  Vector6d xi;
  xi << 1.0 + n(rng), n(rng), n(rng), n(rng), n(rng), n(rng);
  return expSE3(xi);
}

// A positive definite information, anisotropic and with translation-rotation coupling.
Matrix6d randomInformation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  Matrix6d L = Matrix6d::Identity();
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < i; ++j) L(i, j) = u(rng);
    L(i, i) = 1.0 + 3.0 * (u(rng) + 0.3);
  }
  return 100.0 * L * L.transpose();
}

PoseGraphEdge edge(NodeId from, NodeId to, const Eigen::Isometry3d& T, const Matrix6d& information,
                   PoseGraphEdge::Kind kind = PoseGraphEdge::Kind::kOdometry) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = T;
  e.information = information;
  e.kind = kind;
  return e;
}

// The chains, what breaks them (a loop closure, a third edge, an information that is not positive
// definite, the anchor, a pose held constant), and a cycle of two-edge poses alone.
TEST(PoseGraphChains, FindsTheChainsAndWhatEndsThem) {
  std::mt19937 rng(3);
  PoseGraph g;
  std::map<NodeId, Eigen::Isometry3d> initial;
  const auto x = [](uint64_t i) { return NodeId('x', i); };
  for (uint64_t i = 0; i <= 10; ++i) initial[x(i)] = Eigen::Isometry3d::Identity();
  for (uint64_t i = 0; i < 10; ++i)  // odometry x0 - x10, x4 -> x5 stored reversed
    g.edges.push_back(i == 4 ? edge(x(5), x(4), randomStep(rng), randomInformation(rng))
                             : edge(x(i), x(i + 1), randomStep(rng), randomInformation(rng)));
  g.edges.push_back(
      edge(x(2), x(8), randomStep(rng), randomInformation(rng), PoseGraphEdge::Kind::kLoopClosure));
  Matrix6d odd = Matrix6d::Identity();
  odd(0, 0) = -1.0;
  g.edges[6].information = odd;  // x6 - x7 is no chain edge
  // A ring of three poses alone, and an edge to a pose without an initial value.
  for (uint64_t i = 0; i < 3; ++i) {
    initial[NodeId('r', i)] = Eigen::Isometry3d::Identity();
    g.edges.push_back(
        edge(NodeId('r', i), NodeId('r', (i + 1) % 3), randomStep(rng), randomInformation(rng)));
  }
  g.edges.push_back(edge(x(9), NodeId('m', 0), randomStep(rng), randomInformation(rng)));

  const ChainReduction reduction = findChains(g, initial, x(0), {x(4)});
  // x0 (anchor) - x1 - x2 (loop closure): x1; x2 - x3 - x4 (constant): x3; x4 - x5 - x6: x5;
  // x6 - x7 has the odd information; x8 - x9 - x10: x9 (its edge to m0 does not count). The ring
  // keeps one pose, the other two its chain.
  std::map<NodeId, std::pair<NodeId, NodeId>> interior_of;
  for (const PoseGraphChain& chain : reduction.chains) {
    ASSERT_EQ(chain.edges.size(), chain.interior.size() + 1);
    for (const NodeId id : chain.interior) interior_of[id] = {chain.from, chain.to};
  }
  EXPECT_EQ(reduction.chains.size(), 5u);
  EXPECT_EQ(interior_of.size(), 6u);
  for (const uint64_t i : {1, 3, 5, 9}) EXPECT_TRUE(interior_of.count(x(i))) << i;
  for (const uint64_t i : {0, 2, 4, 6, 7, 8, 10}) EXPECT_FALSE(interior_of.count(x(i))) << i;
  size_t ring = 0;
  for (uint64_t i = 0; i < 3; ++i) ring += interior_of.count(NodeId('r', i));
  EXPECT_EQ(ring, 2u);
  // Every edge is in one chain or kept, once.
  std::vector<int> uses(g.edges.size(), 0);
  for (const PoseGraphChain& chain : reduction.chains) {
    for (const size_t k : chain.edges) ++uses[k];
  }
  for (const size_t k : reduction.kept_edges) ++uses[k];
  for (size_t k = 0; k < g.edges.size(); ++k) EXPECT_EQ(uses[k], 1) << "edge " << k;
  // The composed edge is the chain's measurements in order: x4 -> x6 through the reversed one.
  for (size_t c = 0; c < reduction.chains.size(); ++c) {
    const PoseGraphChain& chain = reduction.chains[c];
    if (chain.interior != std::vector<NodeId>{x(5)}) continue;
    const Eigen::Isometry3d expected = chain.from == x(4)
                                           ? g.edges[4].T_from_to.inverse() * g.edges[5].T_from_to
                                           : g.edges[5].T_from_to.inverse() * g.edges[4].T_from_to;
    EXPECT_LT((reduction.composed[c].T_from_to.matrix() - expected.matrix()).norm(), 1e-12);
  }
}

// The composed edge and the placed interior are the chain's first-order optimum: with its ends
// held apart by a misfit, the exact solve of the chain puts the interior where placeChainInteriors
// does, and its cost is the composed edge's, up to terms of second order (a misfit ten times
// smaller: an error about a hundred times smaller).
TEST(PoseGraphChains, InteriorsAtTheChainsOptimum) {
  std::mt19937 rng(11);
  PoseGraph g;
  std::map<NodeId, Eigen::Isometry3d> poses;
  const auto x = [](uint64_t i) { return NodeId('x', i); };
  const int m = 6;
  poses[x(0)] = randomStep(rng);
  for (uint64_t i = 0; i < m; ++i) {
    const Eigen::Isometry3d step = randomStep(rng);
    g.edges.push_back(i % 2 ? edge(x(i + 1), x(i), step.inverse(), randomInformation(rng))
                            : edge(x(i), x(i + 1), step, randomInformation(rng)));
    poses[x(i + 1)] = poses[x(i)] * step;
  }
  const ChainReduction reduction = findChains(g, poses, x(0), {x(m)});
  ASSERT_EQ(reduction.chains.size(), 1u);
  ASSERT_EQ(reduction.chains[0].interior.size(), size_t(m - 1));
  const PoseGraphEdge& composed = reduction.composed[0];

  struct Errors {
    double pose = 0.0;  // largest distance of a placed interior pose from the exact one (m, rad)
    double cost = 0.0;  // |composed cost / exact cost - 1|
  };
  const auto misfitBy = [&](double scale) {
    Vector6d misfit;
    misfit << 0.03, -0.02, 0.04, 0.01, -0.015, 0.02;
    std::map<NodeId, Eigen::Isometry3d> start = poses;
    start[x(m)] = poses.at(x(m)) * expSE3(scale * misfit);
    std::map<NodeId, Eigen::Isometry3d> placed = {{x(0), start[x(0)]}, {x(m), start[x(m)]}};
    placeChainInteriors(g, reduction, placed);
    EXPECT_EQ(placed.size(), size_t(m + 1));
    PoseGraphProblem exact(g, start, x(0), {});
    exact.holdConstant({x(m)});
    const SolveSummary summary = exact.solve();
    EXPECT_TRUE(summary.usable) << summary.message;
    const auto solved = exact.poses();
    Errors errors;
    for (uint64_t i = 1; i < m; ++i) {
      const Eigen::Isometry3d& a = solved.at(x(i));
      const Eigen::Isometry3d& b = placed.at(x(i));
      errors.pose = std::max({errors.pose, (a.translation() - b.translation()).norm(),
                              logSO3(a.linear().transpose() * b.linear()).norm()});
    }
    const Vector6d d = logSE3(composed.T_from_to.inverse() * start[x(0)].inverse() * start[x(m)]);
    errors.cost = std::abs(0.5 * d.dot(composed.information * d) / summary.final_cost - 1.0);
    return errors;
  };
  const Errors large = misfitBy(1.0), small = misfitBy(0.1);
  EXPECT_LT(large.pose, 1e-3);  // of a misfit of 0.05 m and 0.03 rad
  EXPECT_LT(large.cost, 0.02);
  EXPECT_GT(large.pose, 0.0);
  EXPECT_LT(small.pose, 0.03 * large.pose);
  EXPECT_LT(small.cost, 0.3 * large.cost + 1e-4);
}

// Real data: CSAIL's two robots are chains of odometry joined by 378 loop closures, 250 of them
// spurious. GNC over the reduced chains keeps the same loop closures as over every pose, and the
// polish ends at the same optimum.
TEST(PoseGraphChains, CsailWithSpuriousClosuresAsWithoutTheReduction) {
  const std::string dir = testing::dataDir() + "/multirobot/csail_2robots/";
  auto merged = io::readAndMergeG2o({dir + "CSAIL_robot1.g2o", dir + "CSAIL_robot2.g2o",
                                     dir + "CSAIL_interrobot_loop_closures_outliers.g2o"});
  ASSERT_TRUE(merged.ok()) << merged.error();
  const PoseGraph& graph = merged.value().graph;
  const NodeId anchor = graph.edges.front().from;
  // Robot 2 placed through a true loop closure (as the alignment of `pgo --unknown-frames` does).
  auto clean = io::readAndMergeG2o({dir + "CSAIL_robot1.g2o", dir + "CSAIL_robot2.g2o",
                                    dir + "CSAIL_interrobot_loop_closures.g2o"});
  ASSERT_TRUE(clean.ok()) << clean.error();
  const auto initial = spanningInitialization(clean.value().graph, anchor);
  RobustPgoOptions plain;
  plain.reduce_chains = false;
  RobustPgoOptions reduced;
  reduced.chain_min_share = 0.0;
  const RobustPgoResult without = optimizePoseGraph(graph, initial, anchor, plain);
  const RobustPgoResult with = optimizePoseGraph(graph, initial, anchor, reduced);
  ASSERT_TRUE(without.usable && with.usable);
  size_t kept = 0;
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    EXPECT_EQ(with.edge_inlier[k], without.edge_inlier[k]) << "edge " << k;
    kept += graph.edges[k].kind == PoseGraphEdge::Kind::kLoopClosure && with.edge_inlier[k];
  }
  EXPECT_GE(kept, 100u);
  EXPECT_NEAR(with.final_cost, without.final_cost, 1e-3 * without.final_cost);
  ASSERT_EQ(with.poses.size(), without.poses.size());
  for (const auto& [id, pose] : without.poses)
    EXPECT_LT((with.poses.at(id).translation() - pose.translation()).norm(), 0.01) << id.str();
}

}  // namespace
}  // namespace hydra_multi
