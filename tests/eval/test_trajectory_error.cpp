#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/eval/trajectory_error.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

// ATE of ORB-SLAM on KITTI 00 matches the reference tool's figures (data/README.md).
TEST(TrajectoryError, MatchesReferenceOnKitti00) {
  const std::string dir = testing::dataDir() + "/trajectories/";
  auto gt = readKittiPositions(dir + "KITTI_00_gt.txt");
  auto orb = readKittiPositions(dir + "KITTI_00_ORB.txt");
  ASSERT_TRUE(gt.ok()) << gt.error();
  ASSERT_TRUE(orb.ok()) << orb.error();
  ASSERT_EQ(gt.value().size(), 4541u);
  auto ate = absoluteTrajectoryError(orb.value(), gt.value());
  ASSERT_TRUE(ate.ok()) << ate.error();
  const ErrorStatistics& s = ate.value().statistics;
  EXPECT_NEAR(s.rmse, 1.303450, 5e-6);
  EXPECT_NEAR(s.mean, 1.156997, 5e-6);
  EXPECT_NEAR(s.median, 1.065625, 5e-6);
  EXPECT_NEAR(s.std, 0.600282, 5e-6);
  EXPECT_NEAR(s.min, 0.069313, 5e-6);
  EXPECT_NEAR(s.max, 3.587949, 5e-6);
}

// A rigidly moved copy has zero ATE after alignment and its motion's size without.
TEST(TrajectoryError, AlignmentRemovesRigidMotion) {
  std::mt19937 rng(101);
  std::uniform_real_distribution<double> u(-10, 10);
  std::vector<Eigen::Vector3d> reference, moved;
  const Eigen::Isometry3d T = expSE3((Vector6d() << 1, 2, 3, 0.1, 0.2, 0.3).finished());
  for (int i = 0; i < 50; ++i) {
    reference.emplace_back(u(rng), u(rng), u(rng));
    moved.push_back(T * reference.back());
  }
  auto aligned = absoluteTrajectoryError(moved, reference);
  ASSERT_TRUE(aligned.ok());
  EXPECT_LT(aligned.value().statistics.rmse, 1e-9);
  auto raw = absoluteTrajectoryError(moved, reference, false);
  ASSERT_TRUE(raw.ok());
  EXPECT_GT(raw.value().statistics.rmse, 1.0);
  EXPECT_FALSE(absoluteTrajectoryError(moved, {reference.begin(), reference.end() - 1}).ok());
}

}  // namespace
}  // namespace hydra_multi
