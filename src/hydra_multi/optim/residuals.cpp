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

GeodesicResidual::GeodesicResidual(const Eigen::Isometry3d& T_i_j, const Matrix6d& information)
    : q_ij_(T_i_j.linear()), t_ij_(T_i_j.translation()) {
  q_ij_.normalize();
  // S = D^1/2 V^T from information = V D V^T, so ||S e||^2 = e^T information e. Unlike a
  // Cholesky factor it exists for semi-definite information too (negative round-off clamped). An
  // information that is not positive definite is weighed by its nearest positive-definite matrix.
  const Matrix6d weighed = information.llt().info() == Eigen::Success
                               ? information
                               : nearestPositiveDefinite(information);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(0.5 * (weighed + weighed.transpose()));
  sqrt_info_ =
      eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace hydra_multi
