// Pose averaging (eq. 2) by maximum consensus: look-alike rooms give several consistent clusters
// of wrong frame estimates that together outnumber the right ones; the largest cluster wins.
// And held-out robust factors in pose-graph optimization: taken back only where they fit.

#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/optim/pose_averaging.h"
#include "hydra_multi/optim/robust_pose_graph.h"

namespace hydra_multi {
namespace {

Eigen::Isometry3d pose(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() << x, y, 0.0;
  return T;
}

TEST(PoseAveraging, ConsensusFindsTheLargestClusterAmongManyWrongOnes) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Isometry3d truth = pose(12.0, -3.0, 0.4);
  std::vector<Eigen::Isometry3d> estimates;
  const auto jitter = [&](const Eigen::Isometry3d& T) {
    Vector6d xi;
    xi << 0.15 * noise(rng), 0.15 * noise(rng), 0.05 * noise(rng), 0.01 * noise(rng),
        0.01 * noise(rng), 0.02 * noise(rng);
    return T * expSE3(xi);
  };
  for (int i = 0; i < 20; ++i) estimates.push_back(jitter(truth));
  // Three clusters of 15 wrong ones each: one, two and minus one room (3.5 m) along x; 45 of 65.
  for (const double rooms : {1.0, 2.0, -1.0}) {
    for (int i = 0; i < 15; ++i) estimates.push_back(jitter(pose(rooms * 3.5, 0.0, 0.0) * truth));
  }
  PoseAveragingOptions options;
  options.information.setZero();
  options.information.diagonal() << 4.0, 4.0, 4.0, 400.0, 400.0, 400.0;
  options.consensus = true;
  const PoseAverage average = robustPoseAverage(estimates, options).value();
  EXPECT_LT((average.T.translation() - truth.translation()).norm(), 0.15);
  EXPECT_EQ(average.num_inliers, 20u);
  for (size_t k = 0; k < estimates.size(); ++k) EXPECT_EQ(average.inliers[k], k < 20) << k;
  EXPECT_EQ(average.gnc.stop_reason, "consensus");
}

// Weighted consensus: a larger wrong cluster of look-alike matches (support 0) loses to a smaller
// right one whose few distinctive members carry support; without support, or with every support
// zero, the count decides again. A support per estimate is required.
TEST(PoseAveraging, SupportOutweighsCount) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  const auto jitter = [&](const Eigen::Isometry3d& T) {
    Vector6d xi;
    xi << 0.1 * noise(rng), 0.1 * noise(rng), 0.0, 0.0, 0.0, 0.01 * noise(rng);
    return T * expSE3(xi);
  };
  const Eigen::Isometry3d truth = pose(5.0, 2.0, -0.3), wrong = pose(3.4, 0.0, 0.0) * truth;
  std::vector<Eigen::Isometry3d> estimates;
  std::vector<double> support;
  for (int i = 0; i < 8; ++i) {
    estimates.push_back(jitter(truth));
    support.push_back(i < 3 ? 2.5 : 0.0);  // three matches held a kitchen's objects
  }
  for (int i = 0; i < 14; ++i) {
    estimates.push_back(jitter(wrong));
    support.push_back(i == 0 ? 1.0 : 0.0);
  }
  PoseAveragingOptions options;
  options.information.setZero();
  options.information.diagonal() << 4.0, 4.0, 4.0, 400.0, 400.0, 400.0;
  options.consensus = true;
  const PoseAverage weighted = robustPoseAverage(estimates, options, support).value();
  EXPECT_LT((weighted.T.translation() - truth.translation()).norm(), 0.15);
  EXPECT_EQ(weighted.num_inliers, 8u);
  const PoseAverage counted = robustPoseAverage(estimates, options).value();
  EXPECT_LT((counted.T.translation() - wrong.translation()).norm(), 0.15);
  EXPECT_EQ(counted.num_inliers, 14u);
  const PoseAverage zeros =
      robustPoseAverage(estimates, options, std::vector<double>(estimates.size(), 0.0)).value();
  EXPECT_EQ(zeros.num_inliers, 14u);
  const auto mismatched = robustPoseAverage(estimates, options, {1.0, 2.0});
  ASSERT_FALSE(mismatched.ok());
  EXPECT_EQ(mismatched.error(), "pose averaging: 2 supports for 22 estimates");
}

// A robot pair's estimates arriving round after round, wrong clusters first and the right one
// later, the support changing every round: the consensus with its tests kept from the last call
// is the one made afresh, testing only the pairs with a new estimate; an earlier estimate changed
// (a robot revised a keyframe) makes it test all again.
TEST(PoseAveraging, AKeptConsensusIsAFreshOne) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto jitter = [&](const Eigen::Isometry3d& T) {
    Vector6d xi;
    xi << 0.15 * noise(rng), 0.15 * noise(rng), 0.05 * noise(rng), 0.01 * noise(rng),
        0.01 * noise(rng), 0.02 * noise(rng);
    return T * expSE3(xi);
  };
  const Eigen::Isometry3d truth = pose(12.0, -3.0, 0.4), wrong = pose(3.5, 0.0, 0.0) * truth;
  PoseAveragingOptions options;
  options.information.setZero();
  options.information.diagonal() << 4.0, 4.0, 4.0, 400.0, 400.0, 400.0;
  options.consensus = true;
  std::vector<Eigen::Isometry3d> estimates;
  ConsensusCache cache;
  bool turned = false;  // the round whose answer differs from the one before
  Eigen::Isometry3d last = Eigen::Isometry3d::Identity();
  for (int round = 0; round < 8; ++round) {
    for (int i = 0; i < 6; ++i)
      estimates.push_back(jitter(round < 3 ? wrong : truth));
    if (round == 5) estimates[4] = jitter(truth);  // revised
    std::vector<double> support;
    for (size_t k = 0; k < estimates.size(); ++k) support.push_back(unit(rng));
    const size_t before = estimates.size() - 6;
    const PoseAverage fresh = robustPoseAverage(estimates, options, support).value();
    const PoseAverage kept = robustPoseAverage(estimates, options, support, &cache).value();
    EXPECT_TRUE(kept.T.isApprox(fresh.T, 0.0)) << "round " << round;
    EXPECT_EQ(kept.inliers, fresh.inliers) << "round " << round;
    const size_t n = estimates.size();
    EXPECT_EQ(cache.tested, round == 0 || round == 5 ? n * n : n * n - before * before)
        << "round " << round;
    if (round > 0 && !fresh.T.isApprox(last, 1e-6)) turned = true;
    last = fresh.T;
  }
  EXPECT_TRUE(turned);  // the right cluster outgrew the wrong one on the way
  EXPECT_LT((last.translation() - truth.translation()).norm(), 0.15);
}

// A square loop of 8 poses with exact odometry; one right and one wrong loop closure, both held
// out of GNC: the right one fits the result and comes back, the wrong one stays out.
TEST(RobustPoseGraph, HeldOutFactorsComeBackOnlyWhenTheyFit) {
  PoseGraph graph;
  std::map<NodeId, Eigen::Isometry3d> truth;
  for (int k = 0; k < 8; ++k) truth[NodeId('a', k)] = pose(k < 4 ? k : 7 - k, k < 4 ? 0 : 2, 0.0);
  const auto between = [&](int i, int j, const Eigen::Isometry3d& offset,
                           PoseGraphEdge::Kind kind) {
    PoseGraphEdge e;
    e.from = NodeId('a', i);
    e.to = NodeId('a', j);
    e.T_from_to = truth[e.from].inverse() * truth[e.to] * offset;
    e.information = Matrix6d::Identity() * 100.0;
    e.kind = kind;
    graph.edges.push_back(e);
  };
  for (int k = 0; k + 1 < 8; ++k)
    between(k, k + 1, Eigen::Isometry3d::Identity(), PoseGraphEdge::Kind::kOdometry);
  between(0, 7, Eigen::Isometry3d::Identity(), PoseGraphEdge::Kind::kLoopClosure);  // right
  between(1, 6, pose(2.0, 1.0, 0.5), PoseGraphEdge::Kind::kLoopClosure);            // wrong
  RobustPgoOptions options;
  options.held_out.assign(graph.edges.size(), false);
  options.held_out[7] = options.held_out[8] = true;
  const RobustPgoResult result = optimizePoseGraph(graph, truth, NodeId('a', 0), options);
  EXPECT_TRUE(result.edge_inlier[7]);
  EXPECT_FALSE(result.edge_inlier[8]);
  for (const auto& [id, T] : truth)
    EXPECT_LT((result.poses.at(id).translation() - T.translation()).norm(), 1e-6);
}

}  // namespace
}  // namespace hydra_multi
