#include "hydra_multi/optim/residuals.h"

#include <Eigen/Eigenvalues>

namespace hydra_multi {

IsotropicWeights isotropicWeights(const Matrix6d& information) {
  if (information.llt().info() == Eigen::Success) {
    const Matrix6d covariance = information.inverse();
    return {3.0 / (2.0 * covariance.bottomRightCorner<3, 3>().trace()),
            3.0 / covariance.topLeftCorner<3, 3>().trace()};
  }
  // Not positive definite: its inverse is no covariance. SE-Sync's reader takes the translation
  // and rotation blocks of the information itself (tau = 3 / tr(I_t^-1), kappa = 3 / (2
  // tr(I_R^-1)), the same for a block-diagonal matrix).
  return {3.0 / (2.0 * information.bottomRightCorner<3, 3>().inverse().trace()),
          3.0 / information.topLeftCorner<3, 3>().inverse().trace()};
}

Matrix6d nearestPositiveDefinite(const Matrix6d& information) {
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(0.5 *
                                                      (information + information.transpose()));
  const double floor = kPositiveDefiniteFloor * eigen.eigenvalues().cwiseAbs().maxCoeff();
  const Eigen::Matrix<double, 6, 1> clamped = eigen.eigenvalues().cwiseMax(floor);
  return eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
}

namespace {

// A diagonal information with a positive diagonal (the station's, per axis).
bool positiveDiagonal(const Matrix6d& information) {
  for (int c = 0; c < 6; ++c) {
    for (int r = 0; r < 6; ++r) {
      if (r == c ? !(information(r, c) > 0.0) : information(r, c) != 0.0) return false;
    }
  }
  return true;
}

}  // namespace

Matrix6d geodesicSqrtInformation(const Matrix6d& information) {
  // A diagonal information: its square root on the diagonal.
  if (positiveDiagonal(information)) return information.diagonal().cwiseSqrt().asDiagonal();
  // S = D^1/2 V^T from information = V D V^T, so ||S e||^2 = e^T information e. Unlike a
  // Cholesky factor it exists for semi-definite information too (negative round-off clamped). An
  // information that is not positive definite is weighed by its nearest positive-definite matrix.
  const Matrix6d weighed = information.llt().info() == Eigen::Success
                               ? information
                               : nearestPositiveDefinite(information);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(0.5 * (weighed + weighed.transpose()));
  return eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
         eigen.eigenvectors().transpose();
}

GeodesicResidual::GeodesicResidual(const Eigen::Isometry3d& T_i_j, const Matrix6d& information)
    : q_ij_(T_i_j.linear()), t_ij_(T_i_j.translation()) {
  q_ij_.normalize();
  sqrt_info_ = geodesicSqrtInformation(information);
}

namespace {

// Exp(delta) as a unit quaternion.
Eigen::Quaterniond expQuaternion(const Eigen::Vector3d& delta) {
  const double theta = delta.norm();
  if (theta < 1e-10)
    return Eigen::Quaterniond(1.0, 0.5 * delta.x(), 0.5 * delta.y(), 0.5 * delta.z()).normalized();
  const Eigen::Vector3d axis = delta / theta;
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta, axis));
}

// Log of a unit quaternion: the rotation vector of angle in [0, pi].
Eigen::Vector3d logQuaternion(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < 1e-10) return 2.0 * q.vec() / q.w();
  return 2.0 * std::atan2(s, q.w()) * q.vec() / s;
}

}  // namespace

bool LeftQuaternionTangentManifold::Plus(const double* x, const double* delta,
                                         double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Quaterniond> q(x);
  Eigen::Map<Eigen::Quaterniond> result(x_plus_delta);
  result = (expQuaternion(Eigen::Map<const Eigen::Vector3d>(delta)) * q).normalized();
  return true;
}

bool LeftQuaternionTangentManifold::PlusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topRows<3>().setIdentity();
  return true;
}

bool LeftQuaternionTangentManifold::Minus(const double* y, const double* x,
                                          double* y_minus_x) const {
  const Eigen::Map<const Eigen::Quaterniond> qy(y), qx(x);
  Eigen::Map<Eigen::Vector3d> out(y_minus_x);
  out = logQuaternion(qy * qx.conjugate());
  return true;
}

bool LeftQuaternionTangentManifold::MinusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.leftCols<3>().setIdentity();
  return true;
}

GeodesicFactor::GeodesicFactor(const Eigen::Isometry3d& T_i_j, const Matrix6d& information)
    : t_ij_(T_i_j.translation()) {
  R_ij_t_ = Eigen::Quaterniond(T_i_j.linear()).normalized().toRotationMatrix().transpose();
  if (positiveDiagonal(information)) {
    sqrt_diagonal_ = information.diagonal().cwiseSqrt();
  } else {
    sqrt_info_ = std::make_shared<const Matrix6d>(geodesicSqrtInformation(information));
  }
}

void GeodesicFactor::evaluate(const Eigen::Quaterniond& q_i, const Eigen::Vector3d& t_i,
                              const Eigen::Quaterniond& q_j, const Eigen::Vector3d& t_j,
                              Vector6d& r, Matrix6d* J_i, Matrix6d* J_j) const {
  const Eigen::Matrix3d R_i = q_i.toRotationMatrix(), R_j = q_j.toRotationMatrix();
  const Eigen::Matrix3d A = R_ij_t_ * R_i.transpose();  // R_ij^T R_i^T
  const Eigen::Vector3d d = t_j - t_i;
  const Eigen::Vector3d t_e = A * d - R_ij_t_ * t_ij_;
  const Eigen::Vector3d phi = logQuaternion(Eigen::Quaterniond(A * R_j));
  const double theta_sq = phi.squaredNorm();
  double c, dc;           // c(theta) and c'(theta) / theta
  if (theta_sq < 1e-2) {  // series: the closed forms cancel catastrophically near 0
    c = 1.0 / 12.0 + theta_sq / 720.0 + theta_sq * theta_sq / 30240.0;
    dc = 1.0 / 360.0 + theta_sq / 7560.0 + theta_sq * theta_sq / 201600.0;
  } else {
    const double theta = std::sqrt(theta_sq);
    const double cot = std::cos(0.5 * theta) / std::sin(0.5 * theta);
    const double csc_sq = 1.0 / (std::sin(0.5 * theta) * std::sin(0.5 * theta));
    c = 1.0 / theta_sq - cot / (2.0 * theta);
    dc = (-2.0 / (theta_sq * theta) + csc_sq / (4.0 * theta) + cot / (2.0 * theta_sq)) / theta;
  }
  const Eigen::Matrix3d Phi = hat(phi);
  const Eigen::Vector3d phi_x_t = phi.cross(t_e);
  const Eigen::Vector3d phi_x_phi_x_t = phi.cross(phi_x_t);
  Vector6d e;
  e.head<3>() = t_e - 0.5 * phi_x_t + c * phi_x_phi_x_t;
  e.tail<3>() = phi;
  // With a diagonal sqrt_info S, S x is its diagonal times x: the full product's other terms are
  // zeros, which add nothing.
  if (sqrt_info_ != nullptr) {
    r = *sqrt_info_ * e;
  } else {
    r = sqrt_diagonal_.cwiseProduct(e);
  }
  if (J_i == nullptr && J_j == nullptr) return;

  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d W = I - 0.5 * Phi + c * Phi * Phi;
  const Eigen::Matrix3d Jr_inv = I + 0.5 * Phi + c * Phi * Phi;
  const Eigen::Matrix3d P =
      0.5 * hat(t_e) + dc * phi_x_phi_x_t * phi.transpose() +
      c * (phi.dot(t_e) * I + phi * t_e.transpose() - 2.0 * t_e * phi.transpose());
  const Eigen::Matrix3d dphi_dj = Jr_inv * R_j.transpose();
  if (sqrt_info_ == nullptr) {
    // r's rows of rho scale W d t_E + P d phi, its rows of phi d phi alone: the translation's
    // columns are zero there.
    const Eigen::Matrix3d SW = sqrt_diagonal_.head<3>().asDiagonal() * W;
    const Eigen::Matrix3d SP_dphi = sqrt_diagonal_.head<3>().asDiagonal() * P * dphi_dj;
    const Eigen::Matrix3d Sphi_dphi = sqrt_diagonal_.tail<3>().asDiagonal() * dphi_dj;
    const Eigen::Matrix3d SW_A = SW * A;
    if (J_i != nullptr) {
      J_i->topLeftCorner<3, 3>() = SW * (A * hat(d)) - SP_dphi;
      J_i->topRightCorner<3, 3>() = -SW_A;
      J_i->bottomLeftCorner<3, 3>() = -Sphi_dphi;
      J_i->bottomRightCorner<3, 3>().setZero();
    }
    if (J_j != nullptr) {
      J_j->topLeftCorner<3, 3>() = SP_dphi;
      J_j->topRightCorner<3, 3>() = SW_A;
      J_j->bottomLeftCorner<3, 3>() = Sphi_dphi;
      J_j->bottomRightCorner<3, 3>().setZero();
    }
    return;
  }
  // d r / d t_E; d r / d phi, through rho and phi.
  const Eigen::Matrix<double, 6, 3> Sr = sqrt_info_->leftCols<3>() * W;
  const Eigen::Matrix<double, 6, 3> Sphi =
      sqrt_info_->leftCols<3>() * P + sqrt_info_->rightCols<3>();
  if (J_i != nullptr) {
    J_i->leftCols<3>() = Sr * (A * hat(d)) - Sphi * dphi_dj;
    J_i->rightCols<3>() = -Sr * A;
  }
  if (J_j != nullptr) {
    J_j->leftCols<3>() = Sphi * dphi_dj;
    J_j->rightCols<3>() = Sr * A;
  }
}

bool GeodesicCost::Evaluate(double const* const* parameters, double* residuals,
                            double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q_i(parameters[0]), q_j(parameters[2]);
  const Eigen::Map<const Eigen::Vector3d> t_i(parameters[1]), t_j(parameters[3]);
  Vector6d r;
  Matrix6d J_i, J_j;
  const bool any = jacobians != nullptr;
  factor_.evaluate(q_i, t_i, q_j, t_j, r, any ? &J_i : nullptr, any ? &J_j : nullptr);
  Eigen::Map<Vector6d> out(residuals);
  out = r;
  if (!any) return true;
  using Rows4 = Eigen::Map<Eigen::Matrix<double, 6, 4, Eigen::RowMajor>>;
  using Rows3 = Eigen::Map<Eigen::Matrix<double, 6, 3, Eigen::RowMajor>>;
  for (int end = 0; end < 2; ++end) {
    const Matrix6d& J = end == 0 ? J_i : J_j;
    if (double* rotation = jacobians[2 * end]) {
      Rows4 block(rotation);
      block.leftCols<3>() = J.leftCols<3>();
      block.col(3).setZero();
    }
    if (double* translation = jacobians[2 * end + 1]) {
      Rows3 block(translation);
      block = J.rightCols<3>();
    }
  }
  return true;
}

}  // namespace hydra_multi
