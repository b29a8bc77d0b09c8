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

}  // namespace
}  // namespace hydra_multi
