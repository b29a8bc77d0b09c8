#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hydra_multi/core/se3.h"

namespace hydra_multi {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d randomAxisAngle(std::mt19937& rng, double max_angle) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
  axis.normalize();
  return axis * std::uniform_real_distribution<double>(0.0, max_angle)(rng);
}

Vector6d randomTangent(std::mt19937& rng, double max_angle) {
  std::uniform_real_distribution<double> u(-5, 5);
  Vector6d xi;
  xi << u(rng), u(rng), u(rng), randomAxisAngle(rng, max_angle);
  return xi;
}

// exp of the hat matrix agrees with the matrix exponential series, which is independent of
// Rodrigues' formula.
Eigen::Matrix3d seriesExp(const Eigen::Vector3d& phi) {
  Eigen::Matrix3d result = Eigen::Matrix3d::Identity(), term = Eigen::Matrix3d::Identity();
  for (int k = 1; k < 40; ++k) {
    term = term * hat(phi) / k;
    result += term;
  }
  return result;
}

TEST(SO3, HatIsCrossProduct) {
  const Eigen::Vector3d a(1, -2, 3), b(0.5, 4, -1);
  EXPECT_TRUE((hat(a) * b).isApprox(a.cross(b)));
}

// exp matches the series at identity, near identity and at random states; log inverts it.
TEST(SO3, ExpMatchesSeriesAndLogInvertsIt) {
  std::mt19937 rng(1);
  std::vector<Eigen::Vector3d> cases = {Eigen::Vector3d::Zero(), Eigen::Vector3d(1e-12, 0, 0),
                                        Eigen::Vector3d(1e-8, -2e-8, 3e-9),
                                        Eigen::Vector3d(0, 1e-5, 0)};
  for (int i = 0; i < 200; ++i) cases.push_back(randomAxisAngle(rng, kPi - 1e-3));
  for (const auto& phi : cases) {
    const Eigen::Matrix3d R = expSO3(phi);
    EXPECT_LT((R - seriesExp(phi)).norm(), 1e-12) << phi.transpose();
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_LT((logSO3(R) - phi).norm(), 1e-10 * std::max(1.0, phi.norm())) << phi.transpose();
  }
}

// Near pi, log still returns an angle-axis vector that reproduces the rotation.
TEST(SO3, LogNearPi) {
  std::mt19937 rng(2);
  for (int i = 0; i < 50; ++i) {
    Eigen::Vector3d axis = randomAxisAngle(rng, 1.0).normalized();
    for (const double angle : {kPi, kPi - 1e-9, kPi - 1e-4}) {
      const Eigen::Matrix3d R = expSO3(angle * axis);
      const Eigen::Vector3d phi = logSO3(R);
      EXPECT_NEAR(phi.norm(), angle, 1e-7);
      EXPECT_LT((expSO3(phi) - R).norm(), 1e-9);
    }
  }
}

// SE(3): log(exp(xi)) = xi at identity, near identity and random states; exp(log(T)) = T.
TEST(SE3, LogInvertsExp) {
  std::mt19937 rng(3);
  std::vector<Vector6d> cases = {Vector6d::Zero()};
  Vector6d tiny;
  tiny << 1e-3, -2e-3, 5e-4, 1e-9, 2e-9, -1e-9;
  cases.push_back(tiny);
  for (int i = 0; i < 300; ++i) cases.push_back(randomTangent(rng, kPi - 1e-3));
  for (const auto& xi : cases) {
    const Eigen::Isometry3d T = expSE3(xi);
    EXPECT_LT((logSE3(T) - xi).norm(), 1e-9 * std::max(1.0, xi.norm())) << xi.transpose();
    EXPECT_LT((expSE3(logSE3(T)).matrix() - T.matrix()).norm(), 1e-9);
  }
}

// exp(xi) equals the 4x4 matrix exponential of the twist, computed by series.
TEST(SE3, ExpMatchesMatrixExponential) {
  std::mt19937 rng(4);
  for (int i = 0; i < 50; ++i) {
    const Vector6d xi = randomTangent(rng, 2.0);
    Eigen::Matrix4d twist = Eigen::Matrix4d::Zero();
    twist.block<3, 3>(0, 0) = hat(xi.tail<3>());
    twist.block<3, 1>(0, 3) = xi.head<3>();
    Eigen::Matrix4d result = Eigen::Matrix4d::Identity(), term = Eigen::Matrix4d::Identity();
    for (int k = 1; k < 60; ++k) {
      term = term * twist / k;
      result += term;
    }
    EXPECT_LT((expSE3(xi).matrix() - result).norm(), 1e-9);
  }
}

// Composition follows the notation: T_a_c = T_a_b * T_b_c, relativePose recovers T_b_c.
TEST(SE3, RelativePoseAndComposition) {
  std::mt19937 rng(5);
  const Eigen::Isometry3d T_a_b = expSE3(randomTangent(rng, 3.0));
  const Eigen::Isometry3d T_b_c = expSE3(randomTangent(rng, 3.0));
  const Eigen::Isometry3d T_a_c = T_a_b * T_b_c;
  EXPECT_LT((relativePose(T_a_b, T_a_c).matrix() - T_b_c.matrix()).norm(), 1e-12);
  const Eigen::Vector3d p_c(1, 2, 3);
  EXPECT_LT((T_a_c * p_c - T_a_b * (T_b_c * p_c)).norm(), 1e-12);
}

// Interpolation hits both ends, and its midpoint is equidistant on the geodesic.
TEST(SE3, InterpolateAlongGeodesic) {
  std::mt19937 rng(6);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Isometry3d A = expSE3(randomTangent(rng, 3.0));
    const Vector6d delta = randomTangent(rng, 2.5);
    const Eigen::Isometry3d B = A * expSE3(delta);
    EXPECT_LT((interpolate(A, B, 0.0).matrix() - A.matrix()).norm(), 1e-12);
    EXPECT_LT((interpolate(A, B, 1.0).matrix() - B.matrix()).norm(), 1e-9);
    const Eigen::Isometry3d mid = interpolate(A, B, 0.5);
    EXPECT_LT((logSE3(relativePose(A, mid)) - 0.5 * delta).norm(), 1e-9);
  }
}

TEST(SO3, ProjectToSO3) {
  std::mt19937 rng(7);
  const Eigen::Matrix3d R = expSO3(randomAxisAngle(rng, 3.0));
  const Eigen::Matrix3d noisy = R + 1e-3 * Eigen::Matrix3d::Random();
  const Eigen::Matrix3d P = projectToSO3(noisy);
  EXPECT_LT((P.transpose() * P - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(P.determinant(), 1.0, 1e-12);
  EXPECT_LT((P - R).norm(), 1e-2);
  // A reflection is projected to a rotation, not kept.
  EXPECT_NEAR(projectToSO3(-Eigen::Matrix3d::Identity()).determinant(), 1.0, 1e-12);
}

// Umeyama recovers a known rigid transform and a known similarity from exact correspondences,
// and stays close with noise.
TEST(Umeyama, RecoversKnownTransforms) {
  std::mt19937 rng(8);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Isometry3d T = expSE3(randomTangent(rng, 3.0));
    const double scale = 0.5 + trial * 0.1;
    const Eigen::Matrix3Xd src = 5.0 * Eigen::Matrix3Xd::Random(3, 50);
    const Eigen::Matrix3Xd rigid = T * src;
    const Eigen::Matrix3Xd similar = (scale * (T.linear() * src)).colwise() + T.translation();

    const auto r = umeyamaAlignment(src, rigid, false);
    ASSERT_TRUE(r.has_value());
    EXPECT_LT((r->T_dst_src.matrix() - T.matrix()).norm(), 1e-9);
    EXPECT_EQ(r->scale, 1.0);

    const auto s = umeyamaAlignment(src, similar, true);
    ASSERT_TRUE(s.has_value());
    EXPECT_NEAR(s->scale, scale, 1e-9);
    EXPECT_LT((s->T_dst_src.linear() - T.linear()).norm(), 1e-9);
    EXPECT_LT((s->T_dst_src.translation() - T.translation()).norm(), 1e-9);

    Eigen::Matrix3Xd noisy = rigid;
    for (int i = 0; i < noisy.size(); ++i) noisy.data()[i] += noise(rng);
    const auto n = umeyamaAlignment(src, noisy, false);
    ASSERT_TRUE(n.has_value());
    EXPECT_LT(logSE3(relativePose(T, n->T_dst_src)).norm(), 0.02);
  }
}

TEST(Umeyama, RejectsDegenerateInput) {
  const Eigen::Matrix3Xd two = Eigen::Matrix3Xd::Random(3, 2);
  EXPECT_FALSE(umeyamaAlignment(two, two, false).has_value());
  Eigen::Matrix3Xd line(3, 5);
  for (int i = 0; i < 5; ++i) line.col(i) = Eigen::Vector3d(1, 2, 3) * i;
  EXPECT_FALSE(umeyamaAlignment(line, line, false).has_value());
  Eigen::Matrix3Xd bad = Eigen::Matrix3Xd::Random(3, 5);
  bad(1, 2) = std::nan("");
  EXPECT_FALSE(umeyamaAlignment(bad, bad, false).has_value());
  EXPECT_FALSE(
      umeyamaAlignment(Eigen::Matrix3Xd::Random(3, 5), Eigen::Matrix3Xd::Random(3, 6), false)
          .has_value());
}

}  // namespace
}  // namespace hydra_multi
