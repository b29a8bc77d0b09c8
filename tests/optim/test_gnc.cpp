#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/optim/gnc.h"
#include "hydra_multi/optim/pose_averaging.h"

namespace hydra_multi {
namespace {

// Chi-square quantiles against tabulated values.
TEST(Gnc, ChiSquaredQuantiles) {
  EXPECT_NEAR(chiSquaredQuantile(1, 0.95), 3.841459, 1e-5);
  EXPECT_NEAR(chiSquaredQuantile(3, 0.99), 11.344867, 1e-5);
  EXPECT_NEAR(chiSquaredQuantile(6, 0.99), 16.811894, 1e-5);
  EXPECT_NEAR(chiSquaredQuantile(6, 0.5), 5.348121, 1e-5);
  EXPECT_NEAR(GncOptions{}.thresholdSq(), 16.811894, 1e-5);
}

// TLS weights against hand-computed values (c^2 = 1, mu = 1: the band is r^2 in [1/2, 2]).
TEST(Gnc, TlsWeightsByHand) {
  EXPECT_EQ(tlsWeight(0.5, 1.0, 1.0), 1.0);
  EXPECT_EQ(tlsWeight(2.0, 1.0, 1.0), 0.0);
  EXPECT_NEAR(tlsWeight(1.0, 1.0, 1.0), std::sqrt(2.0) - 1.0, 1e-15);
  // c^2 = 4, mu = 3: w = 2 sqrt(12) / r - 3 at r^2 = 4 (r = 2).
  EXPECT_NEAR(tlsWeight(4.0, 3.0, 4.0), std::sqrt(12.0) - 3.0, 1e-15);
  // Continuous at the band's ends.
  EXPECT_NEAR(tlsWeight(0.5 + 1e-12, 1.0, 1.0), 1.0, 1e-9);
  EXPECT_NEAR(tlsWeight(2.0 - 1e-12, 1.0, 1.0), 0.0, 1e-9);
}

// GNC finds the inliers of a robust mean with 60 % gross outliers; least squares alone would not.
TEST(Gnc, RobustMeanWithOutliers) {
  std::mt19937 rng(91);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::uniform_real_distribution<double> wild(-50.0, 50.0);
  std::vector<double> values;
  std::vector<bool> truth;
  for (int i = 0; i < 100; ++i) {
    const bool inlier = i % 5 < 2;
    values.push_back(inlier ? 3.0 + noise(rng) : wild(rng));
    truth.push_back(inlier);
  }
  double estimate = 0.0;
  const auto solve = [&](const std::vector<double>& w) {
    double num = 0.0, den = 0.0;
    for (size_t k = 0; k < values.size(); ++k) {
      num += w[k] * values[k];
      den += w[k];
    }
    estimate = den > 0 ? num / den : estimate;
    WeightedSolution s;
    for (size_t k = 0; k < values.size(); ++k) {
      const double r = (values[k] - estimate) / 0.1;
      s.squared_residuals.push_back(r * r);
      s.cost += w[k] * r * r;
    }
    return s;
  };
  GncOptions options;
  options.residual_dof = 1;
  const GncResult result = runGnc(values.size(), solve, options);
  EXPECT_NEAR(estimate, 3.0, 0.05);
  // Every outlier rejected; inliers kept but for the ~1 % of Gaussian noise beyond the 0.99
  // chi-square threshold.
  size_t kept = 0, wrong = 0;
  for (size_t k = 0; k < truth.size(); ++k) {
    kept += (truth[k] && result.inliers[k]) ? 1 : 0;
    wrong += (!truth[k] && result.inliers[k]) ? 1 : 0;
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GE(kept, 38u);  // of 40
  EXPECT_NE(result.stop_reason, "max iterations");
}

// Without outliers, GNC stops at once with everything an inlier.
TEST(Gnc, NoOutliersStopsImmediately) {
  const auto solve = [](const std::vector<double>& w) {
    return WeightedSolution{std::vector<double>(w.size(), 0.5), 1.0};
  };
  const GncResult result = runGnc(10, solve);
  EXPECT_EQ(result.stop_reason, "no outliers");
  EXPECT_EQ(result.num_inliers, 10u);
  EXPECT_EQ(result.iterations, 0);
}

// eq. (2): the robust average of noisy estimates of one transform among 70 % random outliers.
TEST(PoseAveraging, RecoversTransformAmongOutliers) {
  std::mt19937 rng(92);
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Isometry3d truth = expSE3((Vector6d() << 4, -2, 1, 0.3, -0.2, 1.2).finished());
  std::vector<Eigen::Isometry3d> estimates;
  std::vector<bool> labels;
  for (int k = 0; k < 40; ++k) {
    Vector6d xi;
    const bool inlier = k % 10 < 3;
    for (int i = 0; i < 6; ++i) xi[i] = inlier ? 0.02 * noise(rng) : 3.0 * noise(rng);
    estimates.push_back(truth * expSE3(xi));
    labels.push_back(inlier);
  }
  PoseAveragingOptions options;
  options.information = Matrix6d::Identity() / (0.02 * 0.02);
  auto average = robustPoseAverage(estimates, options);
  ASSERT_TRUE(average.ok()) << average.error();
  EXPECT_LT(logSE3(relativePose(truth, average.value().T)).norm(), 0.03);
  EXPECT_EQ(average.value().inliers, labels);
  EXPECT_EQ(average.value().num_inliers, 12u);
  EXPECT_FALSE(robustPoseAverage({}).ok());
}

// The weighted average is the exact mean when the estimates are rotations about one axis.
TEST(PoseAveraging, WeightedAverageOfConsistentEstimates) {
  std::vector<Eigen::Isometry3d> estimates;
  for (const double angle : {0.1, 0.2, 0.3}) {
    estimates.push_back(expSE3((Vector6d() << 0, 0, 0, 0, 0, angle).finished()));
  }
  auto mean = weightedPoseAverage(estimates, {1, 1, 1}, Eigen::Isometry3d::Identity(), 50);
  ASSERT_TRUE(mean.ok());
  EXPECT_NEAR(logSO3(mean.value().linear()).z(), 0.2, 1e-12);
  EXPECT_FALSE(weightedPoseAverage(estimates, {0, 0, 0}, Eigen::Isometry3d::Identity(), 5).ok());
}

}  // namespace
}  // namespace hydra_multi
