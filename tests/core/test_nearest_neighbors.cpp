#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {
namespace {

// A radius search finds exactly the points a brute-force scan finds, by increasing index.
TEST(NearestNeighbors, WithinRadiusMatchesBruteForce) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-5, 5);
  std::vector<Eigen::Vector3d> points(400);
  for (auto& p : points) p = {u(rng), u(rng), u(rng)};
  const NearestNeighbors index(points);
  for (int q = 0; q < 50; ++q) {
    const Eigen::Vector3d query(u(rng), u(rng), u(rng));
    std::vector<size_t> brute;
    for (size_t i = 0; i < points.size(); ++i) {
      if ((points[i] - query).norm() <= 2.0) brute.push_back(i);
    }
    const auto found = index.withinRadius(query, 2.0);
    ASSERT_EQ(found.size(), brute.size());
    for (size_t k = 0; k < found.size(); ++k) {
      EXPECT_EQ(found[k].index, brute[k]);
      EXPECT_NEAR(found[k].distance, (points[brute[k]] - query).norm(), 1e-12);
    }
  }
  EXPECT_TRUE(NearestNeighbors({}).withinRadius(Eigen::Vector3d::Zero(), 1.0).empty());
}

// The KD-tree returns what a brute-force search returns, nearest first.
TEST(NearestNeighbors, MatchesBruteForce) {
  std::mt19937 rng(121);
  std::uniform_real_distribution<double> u(-10, 10);
  std::vector<Eigen::Vector3d> points(500);
  for (auto& p : points) p = {u(rng), u(rng), u(rng)};
  const NearestNeighbors index(points);
  EXPECT_EQ(index.size(), 500u);
  for (int q = 0; q < 100; ++q) {
    const Eigen::Vector3d query(u(rng), u(rng), u(rng));
    std::vector<std::pair<double, size_t>> brute;
    for (size_t i = 0; i < points.size(); ++i) brute.emplace_back((points[i] - query).norm(), i);
    std::sort(brute.begin(), brute.end());
    const auto found = index.nearest(query, 4);
    ASSERT_EQ(found.size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(found[k].index, brute[k].second);
      EXPECT_NEAR(found[k].distance, brute[k].first, 1e-12);
    }
  }
}

TEST(NearestNeighbors, EmptyAndSmallSets) {
  const NearestNeighbors empty({});
  EXPECT_TRUE(empty.nearest(Eigen::Vector3d::Zero()).empty());
  const NearestNeighbors two({Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(3, 0, 0)});
  const auto all = two.nearest(Eigen::Vector3d::Zero(), 5);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].index, 0u);
  EXPECT_DOUBLE_EQ(all[1].distance, 3.0);
}

// A robot's two passes over one place: the query counts only the points made within the window of
// its time, nearest first, even where the other pass's points lie nearer.
TEST(TimedNeighbors, OnlyPointsOfAboutTheQuerysTime) {
  constexpr int64_t kS = 1000000000;
  // Indices 0-2: the first pass at t = 0-2 s; 3-4: the second at t = 100-101 s, 0.1 m away.
  const std::vector<Eigen::Vector3d> points = {
      {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0.1, 0, 0}, {1.1, 0, 0}};
  const std::vector<int64_t> times = {0, 1 * kS, 2 * kS, 100 * kS, 101 * kS};
  const TimedNeighbors timed(points, times, 10 * kS);
  EXPECT_EQ(timed.size(), 5u);
  const auto first = timed.nearest(Eigen::Vector3d(0.12, 0, 0), 1 * kS, 2);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].index, 0u);
  EXPECT_EQ(first[1].index, 1u);
  EXPECT_NEAR(first[0].distance, 0.12, 1e-12);
  const auto second = timed.nearest(Eigen::Vector3d(0.12, 0, 0), 95 * kS, 5);
  ASSERT_EQ(second.size(), 2u);  // the window holds two
  EXPECT_EQ(second[0].index, 3u);
  EXPECT_EQ(second[1].index, 4u);
  // No point within 10 s of t = 50 s: the window moves to the nearest time with points, 2 s
  // (48 s away; 100 s is 50 s away), the first pass.
  const auto between = timed.nearest(Eigen::Vector3d(0.12, 0, 0), 50 * kS, 1);
  ASSERT_EQ(between.size(), 1u);
  EXPECT_EQ(between[0].index, 0u);
  // Without a window every point counts.
  const TimedNeighbors any(points, times, 0);
  EXPECT_EQ(any.nearest(Eigen::Vector3d(0.12, 0, 0), 1 * kS).front().index, 3u);
  EXPECT_EQ(any.size(), 5u);
  EXPECT_TRUE(TimedNeighbors({}, {}, 10 * kS).nearest(Eigen::Vector3d::Zero(), 0).empty());
  EXPECT_THROW(TimedNeighbors(points, {0}, 10 * kS), std::invalid_argument);
}

}  // namespace
}  // namespace hydra_multi
