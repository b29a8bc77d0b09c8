#include "hydra_multi/core/se3.h"

#include <Eigen/SVD>
#include <cmath>

namespace hydra_multi {
namespace {

constexpr double kSmallAngle = 1e-6;

// The matrix V(phi) of the header's derivation.
Eigen::Matrix3d leftJacobianV(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = hat(phi);
  double a, b;  // coefficients of hat(phi) and hat(phi)^2
  if (theta < kSmallAngle) {
    const double t2 = theta * theta;
    a = 0.5 - t2 / 24.0;
    b = 1.0 / 6.0 - t2 / 120.0;
  } else {
    a = (1.0 - std::cos(theta)) / (theta * theta);
    b = (theta - std::sin(theta)) / (theta * theta * theta);
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

// The matrix V(phi)^-1 of the header's derivation.
Eigen::Matrix3d leftJacobianVInverse(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = hat(phi);
  double c;  // coefficient of hat(phi)^2
  if (theta < kSmallAngle) {
    c = 1.0 / 12.0 + theta * theta / 720.0;
  } else {
    const double half = 0.5 * theta;
    c = 1.0 / (theta * theta) - std::cos(half) / (2.0 * theta * std::sin(half));
  }
  return Eigen::Matrix3d::Identity() - 0.5 * K + c * K * K;
}

}  // namespace

Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0.0, -w.z(), w.y(),  //
      w.z(), 0.0, -w.x(),   //
      -w.y(), w.x(), 0.0;
  return W;
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  if (theta < kSmallAngle) {
    // Second-order series; exact to double precision at this size.
    const Eigen::Matrix3d K = hat(phi);
    return projectToSO3(Eigen::Matrix3d::Identity() + K + 0.5 * K * K);
  }
  return Eigen::AngleAxisd(theta, phi / theta).toRotationMatrix();
}

Eigen::Vector3d logSO3(const Eigen::Matrix3d& R) {
  // Through the unit quaternion, which stays accurate near 0 and near pi.
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double vec_norm = q.vec().norm();
  if (vec_norm < 1e-12) return 2.0 * q.vec();  // sin(theta/2) ~ theta/2
  const double theta = 2.0 * std::atan2(vec_norm, q.w());
  return theta * q.vec() / vec_norm;
}

Eigen::Isometry3d expSE3(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = expSO3(phi);
  T.translation() = leftJacobianV(phi) * rho;
  return T;
}

Vector6d logSE3(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d phi = logSO3(T.linear());
  Vector6d xi;
  xi.head<3>() = leftJacobianVInverse(phi) * T.translation();
  xi.tail<3>() = phi;
  return xi;
}

Eigen::Isometry3d relativePose(const Eigen::Isometry3d& T_a_b, const Eigen::Isometry3d& T_a_c) {
  return T_a_b.inverse() * T_a_c;
}

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& T_a, const Eigen::Isometry3d& T_b,
                              double s) {
  return T_a * expSE3(s * logSE3(relativePose(T_a, T_b)));
}

Eigen::Matrix3d projectToSO3(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

std::optional<Similarity3> umeyamaAlignment(const Eigen::Matrix3Xd& src,
                                            const Eigen::Matrix3Xd& dst, bool with_scale) {
  if (src.cols() != dst.cols() || src.cols() < 3) return std::nullopt;
  if (!src.allFinite() || !dst.allFinite()) return std::nullopt;
  // Collinear or coincident points leave the rotation about their line undetermined: the second
  // singular value of the centred source points is then (numerically) zero.
  const Eigen::Matrix3Xd centred = src.colwise() - src.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred);
  const Eigen::Vector3d sigma = svd.singularValues();
  if (sigma(1) <= 1e-9 * std::max(1.0, sigma(0))) return std::nullopt;

  const Eigen::Matrix4d M = Eigen::umeyama(src, dst, with_scale);
  if (!M.allFinite()) return std::nullopt;
  Similarity3 result;
  result.scale = with_scale ? M.block<3, 3>(0, 0).col(0).norm() : 1.0;
  result.T_dst_src.linear() = M.block<3, 3>(0, 0) / result.scale;
  result.T_dst_src.translation() = M.block<3, 1>(0, 3);
  return result;
}

Matrix6d informationFromVariances(double translation_variance, double rotation_variance) {
  Matrix6d information = Matrix6d::Zero();
  information.diagonal() << Eigen::Vector3d::Constant(1.0 / translation_variance),
      Eigen::Vector3d::Constant(1.0 / rotation_variance);
  return information;
}

}  // namespace hydra_multi
