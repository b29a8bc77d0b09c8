#include <gtest/gtest.h>

#include <fstream>
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

// Association pairs each estimate with its nearest unused reference stamp within the limit.
TEST(TrajectoryError, AssociatesByNearestStamp) {
  const std::vector<double> est = {0.0, 1.0, 2.004, 3.5, 4.0};
  const std::vector<double> ref = {0.001, 0.998, 1.003, 2.0, 4.02};
  const auto pairs = associateByTime(est, ref, 0.01);
  const std::vector<std::pair<size_t, size_t>> expected = {{0, 0}, {1, 1}, {2, 3}};
  EXPECT_EQ(pairs, expected);
  EXPECT_EQ(associateByTime(est, ref, 0.05).size(), 4u);  // 4.0 - 4.02 now counts
  EXPECT_TRUE(associateByTime({}, ref, 1.0).empty());
}

// TUM files: comments skipped, eight numbers per line, increasing stamps; errors name the line.
TEST(TrajectoryError, ReadsTumFiles) {
  const std::string path = ::testing::TempDir() + "traj.tum";
  {
    std::ofstream out(path);
    out << "# timestamp tx ty tz qx qy qz qw\n1.0 1 2 3 0 0 0 1\n2.0 4 5 6 0 0 0 1\n";
  }
  auto t = readTumTrajectory(path);
  ASSERT_TRUE(t.ok()) << t.error();
  EXPECT_EQ(t.value().stamps, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(t.value().positions[1], Eigen::Vector3d(4, 5, 6));
  {
    std::ofstream out(path);
    out << "1.0 1 2 3 0 0 0 1\n0.5 4 5 6 0 0 0 1\n";
  }
  EXPECT_NE(readTumTrajectory(path).error().find(":2: timestamps must increase"),
            std::string::npos);
  {
    std::ofstream out(path);
    out << "1.0 1 2 3 0 0 0\n";
  }
  EXPECT_NE(readTumTrajectory(path).error().find(":1: expected 8 finite numbers"),
            std::string::npos);
  // More numbers than a TUM line holds is not a TUM file (a KITTI one, say); nor is one without
  // a pose.
  {
    std::ofstream out(path);
    out << "1.0 1 2 3 0 0 0 1 7\n";
  }
  EXPECT_EQ(readTumTrajectory(path).error(),
            path + ":1: expected 8 numbers (t tx ty tz qx qy qz qw), found more ('7')");
  {
    std::ofstream out(path);
    out << "# only a comment\n";
  }
  EXPECT_EQ(readTumTrajectory(path).error(),
            path + ": no pose (a TUM file has one 't tx ty tz qx qy qz qw' per line)");
}

// KITTI files: twelve numbers a line, no more; a file without a pose is refused.
TEST(TrajectoryError, KittiLinesHoldTwelveNumbers) {
  const std::string path = ::testing::TempDir() + "traj.kitti";
  {
    std::ofstream out(path);
    out << "1 0 0 0 0 1 0 0 0 0 1 0 5\n";
  }
  EXPECT_EQ(readKittiPositions(path).error(), path + ":1: expected 12 numbers, found more ('5')");
  {
    std::ofstream out(path);
    out << "\n";
  }
  EXPECT_EQ(readKittiPositions(path).error(),
            path + ": no pose (a KITTI file has one 3x4 pose per line)");
}

}  // namespace
}  // namespace hydra_multi
