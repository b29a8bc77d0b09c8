#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/optim/residuals.h"

namespace hydra_multi {
namespace {

struct Pose {
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
};

Pose randomPose(std::mt19937& rng, double angle_scale, double translation_scale) {
  std::normal_distribution<double> n;
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi[i] = n(rng);
  xi.head<3>() *= translation_scale;
  xi.tail<3>() *= angle_scale;
  const Eigen::Isometry3d T = expSE3(xi);
  return {Eigen::Quaterniond(T.linear()), T.translation()};
}

Eigen::Isometry3d toIso(const Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = p.q.toRotationMatrix();
  T.translation() = p.t;
  return T;
}

Matrix6d randomInformation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Matrix6d A;
  for (int i = 0; i < 36; ++i) A.data()[i] = u(rng);
  return A * A.transpose() + 0.5 * Matrix6d::Identity();
}

// Tangent-space Jacobians of a residual: analytic (autodiff, through the manifold's PlusJacobian)
// and by central differences through the manifold's Plus.
struct TangentJacobians {
  std::vector<Eigen::MatrixXd> analytic, numeric;
};

TangentJacobians tangentJacobians(
    const ceres::CostFunction& cost, const Pose& i, const Pose& j, double h,
    const ceres::Manifold& quaternion = ceres::EigenQuaternionManifold()) {
  const int m = cost.num_residuals();
  std::vector<Eigen::VectorXd> x = {i.q.coeffs(), i.t, j.q.coeffs(), j.t};
  auto evaluate = [&](const std::vector<Eigen::VectorXd>& values, std::vector<Eigen::MatrixXd>* J) {
    const double* parameters[4] = {values[0].data(), values[1].data(), values[2].data(),
                                   values[3].data()};
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> ambient;
    double* jacobians[4] = {nullptr, nullptr, nullptr, nullptr};
    if (J) {
      for (size_t b = 0; b < 4; ++b) ambient.emplace_back(m, values[b].size());
      for (size_t b = 0; b < 4; ++b) jacobians[b] = ambient[b].data();
    }
    Eigen::VectorXd r(m);
    cost.Evaluate(parameters, r.data(), J ? jacobians : nullptr);
    if (J) {
      for (size_t b = 0; b < 4; ++b) {
        if (b % 2 == 0) {
          Eigen::Matrix<double, 4, 3, Eigen::RowMajor> plus;
          quaternion.PlusJacobian(values[b].data(), plus.data());
          J->push_back(ambient[b] * plus);
        } else {
          J->push_back(ambient[b]);
        }
      }
    }
    return r;
  };
  TangentJacobians result;
  evaluate(x, &result.analytic);
  for (size_t b = 0; b < 4; ++b) {
    Eigen::MatrixXd N(m, 3);
    for (int k = 0; k < 3; ++k) {
      std::vector<Eigen::VectorXd> plus = x, minus = x;
      Eigen::Vector3d delta = Eigen::Vector3d::Zero();
      delta[k] = h;
      if (b % 2 == 0) {
        quaternion.Plus(x[b].data(), delta.data(), plus[b].data());
        delta[k] = -h;
        quaternion.Plus(x[b].data(), delta.data(), minus[b].data());
      } else {
        plus[b] += delta;
        minus[b] -= delta;
      }
      N.col(k) = (evaluate(plus, nullptr) - evaluate(minus, nullptr)) / (2 * h);
    }
    result.numeric.push_back(N);
  }
  return result;
}

// Jacobians of both residuals match central differences on the quaternion manifold at identity,
// near identity and random states.
TEST(Residuals, JacobiansMatchNumericDifferentiation) {
  std::mt19937 rng(71);
  struct Scale {
    double angle, translation;
  };
  for (const Scale scale : {Scale{0, 0}, Scale{1e-4, 1e-3}, Scale{1.0, 3.0}}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Pose i = randomPose(rng, scale.angle, scale.translation);
      const Pose j = randomPose(rng, scale.angle, scale.translation);
      const Eigen::Isometry3d measured =
          scale.angle == 0 ? Eigen::Isometry3d::Identity() : toIso(randomPose(rng, 0.5, 1.0));
      const Matrix6d info = randomInformation(rng);
      std::unique_ptr<ceres::CostFunction> chordal(
          ChordalResidual::Create(measured, isotropicWeights(info)));
      std::unique_ptr<ceres::CostFunction> geodesic(GeodesicResidual::Create(measured, info));
      for (const ceres::CostFunction* cost : {chordal.get(), geodesic.get()}) {
        const TangentJacobians J = tangentJacobians(*cost, i, j, 1e-6);
        for (size_t b = 0; b < 4; ++b) {
          EXPECT_LE((J.analytic[b] - J.numeric[b]).norm(), 1e-6 * (1.0 + J.numeric[b].norm()))
              << "block " << b << ", angle scale " << scale.angle << ", "
              << (cost == chordal.get() ? "chordal" : "geodesic");
        }
      }
    }
  }
}

// The geodesic cost with closed-form Jacobians: the automatic residual's value, and Jacobians that
// match central differences on its manifold, at identity, near it, across the series' switch
// (an error of about 0.1 rad), at random states and with errors near pi; with a full information
// and with a diagonal one (kept as its diagonal).
TEST(Residuals, GeodesicCostMatchesItsAutomaticTwin) {
  std::mt19937 rng(73);
  const LeftQuaternionTangentManifold manifold;
  struct Scale {
    double angle, translation, measured_angle;
  };
  for (const Scale scale : {Scale{0, 0, 0}, Scale{1e-4, 1e-3, 1e-4}, Scale{0.05, 1.0, 0.05},
                            Scale{1.0, 3.0, 0.5}, Scale{0.0, 2.0, 3.1}}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Pose i = randomPose(rng, scale.angle, scale.translation);
      const Pose j = randomPose(rng, scale.angle, scale.translation);
      Eigen::Isometry3d measured = toIso(randomPose(rng, scale.measured_angle, 1.0));
      if (scale.measured_angle > 3.0) {  // turned nearly pi about a random axis
        const Eigen::Vector3d axis = toIso(randomPose(rng, 1.0, 1.0)).translation().normalized();
        measured.linear() = Eigen::AngleAxisd(3.1 + 0.04 * trial / 20.0, axis).toRotationMatrix();
      }
      Matrix6d info = randomInformation(rng);
      if (trial % 2 == 1) info = Matrix6d(info.diagonal().asDiagonal());
      const GeodesicCost cost(measured, info);
      std::unique_ptr<ceres::CostFunction> twin(GeodesicResidual::Create(measured, info));
      const double* parameters[4] = {i.q.coeffs().data(), i.t.data(), j.q.coeffs().data(),
                                     j.t.data()};
      Eigen::Matrix<double, 6, 1> r, r_twin;
      ASSERT_TRUE(cost.Evaluate(parameters, r.data(), nullptr));
      ASSERT_TRUE(twin->Evaluate(parameters, r_twin.data(), nullptr));
      EXPECT_LE((r - r_twin).norm(), 1e-9 * (1.0 + r_twin.norm())) << "angle " << scale.angle;
      const TangentJacobians J = tangentJacobians(cost, i, j, 1e-6, manifold);
      for (size_t b = 0; b < 4; ++b) {
        EXPECT_LE((J.analytic[b] - J.numeric[b]).norm(), 1e-6 * (1.0 + J.numeric[b].norm()))
            << "block " << b << ", angle scale " << scale.angle << ", measured "
            << scale.measured_angle;
      }
    }
  }
}

// The manifold: Plus turns by Exp(delta) on the left, Minus undoes it.
TEST(Residuals, LeftQuaternionTangentManifoldPlusAndMinus) {
  const LeftQuaternionTangentManifold manifold;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d delta(0.1, -0.2, 0.3);
  Eigen::Quaterniond moved;
  ASSERT_TRUE(manifold.Plus(q.coeffs().data(), delta.data(), moved.coeffs().data()));
  const Eigen::Quaterniond expected =
      Eigen::Quaterniond(Eigen::AngleAxisd(delta.norm(), delta.normalized())) * q;
  EXPECT_LE(moved.angularDistance(expected), 1e-12);
  Eigen::Vector3d back;
  ASSERT_TRUE(manifold.Minus(moved.coeffs().data(), q.coeffs().data(), back.data()));
  EXPECT_LE((back - delta).norm(), 1e-12);
}

// The geodesic residual is sqrt_info * log(T_ij^-1 T_i^-1 T_j), computed here with core's SE(3)
// log (an independent implementation); the chordal one squares to the SE-Sync cost term.
TEST(Residuals, ValuesMatchTheirDefinitions) {
  std::mt19937 rng(72);
  for (int trial = 0; trial < 50; ++trial) {
    Pose i = randomPose(rng, 1.0, 3.0), j = randomPose(rng, 1.0, 3.0);
    const Eigen::Isometry3d measured = toIso(randomPose(rng, 1.0, 3.0));
    const Matrix6d info = randomInformation(rng);
    const double* parameters[4] = {i.q.coeffs().data(), i.t.data(), j.q.coeffs().data(),
                                   j.t.data()};
    std::unique_ptr<ceres::CostFunction> geodesic(GeodesicResidual::Create(measured, info));
    Vector6d r;
    geodesic->Evaluate(parameters, r.data(), nullptr);
    const Vector6d e = logSE3(measured.inverse() * toIso(i).inverse() * toIso(j));
    EXPECT_NEAR(r.squaredNorm(), e.dot(info * e), 1e-8 * (1 + e.dot(info * e)));

    const IsotropicWeights w = isotropicWeights(info);
    std::unique_ptr<ceres::CostFunction> chordal(ChordalResidual::Create(measured, w));
    Eigen::Matrix<double, 12, 1> c;
    chordal->Evaluate(parameters, c.data(), nullptr);
    const Eigen::Isometry3d Ti = toIso(i), Tj = toIso(j);
    const double expected =
        w.kappa * (Tj.linear() - Ti.linear() * measured.linear()).squaredNorm() +
        w.tau * (Tj.translation() - Ti.translation() - Ti.linear() * measured.translation())
                    .squaredNorm();
    EXPECT_NEAR(c.squaredNorm(), expected, 1e-9 * (1 + expected));
  }
}

// tau and kappa as data/README.md defines them.
TEST(Residuals, IsotropicWeightsFromInformation) {
  Matrix6d info = Matrix6d::Zero();
  info.diagonal() << 10, 10, 10, 400, 400, 100;
  const IsotropicWeights w = isotropicWeights(info);
  EXPECT_NEAR(w.tau, 3.0 / 0.3, 1e-12);
  EXPECT_NEAR(w.kappa, 3.0 / (2.0 * (1.0 / 400 + 1.0 / 400 + 1.0 / 100)), 1e-12);
}

// S^T S is the information, per axis (the station's) or full; an information that is not positive
// definite is weighed by its nearest positive-definite matrix.
TEST(Residuals, GeodesicSqrtInformation) {
  Matrix6d axes = Matrix6d::Zero();
  axes.diagonal() << 100, 100, 100, 1e4, 1e4, 25;
  const Matrix6d s_axes = geodesicSqrtInformation(axes);
  EXPECT_TRUE((s_axes.transpose() * s_axes).isApprox(axes, 1e-15));
  EXPECT_DOUBLE_EQ(s_axes(5, 5), 5.0);
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  Matrix6d a;
  for (int i = 0; i < 36; ++i) a(i / 6, i % 6) = n(rng);
  const Matrix6d full = a * a.transpose() + Matrix6d::Identity();
  const Matrix6d s_full = geodesicSqrtInformation(full);
  EXPECT_TRUE((s_full.transpose() * s_full).isApprox(full, 1e-12));
  Matrix6d odd = axes;
  odd(3, 3) = -50.0;
  const Matrix6d s_odd = geodesicSqrtInformation(odd);
  EXPECT_TRUE((s_odd.transpose() * s_odd).isApprox(nearestPositiveDefinite(odd), 1e-12));
}

}  // namespace
}  // namespace hydra_multi
