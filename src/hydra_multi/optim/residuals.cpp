#include "hydra_multi/optim/residuals.h"

#include <Eigen/Eigenvalues>

namespace hydra_multi {

IsotropicWeights isotropicWeights(const Matrix6d& information) {
  const Matrix6d covariance = information.inverse();
  return {3.0 / (2.0 * covariance.bottomRightCorner<3, 3>().trace()),
          3.0 / covariance.topLeftCorner<3, 3>().trace()};
}

GeodesicResidual::GeodesicResidual(const Eigen::Isometry3d& T_i_j, const Matrix6d& information)
    : q_ij_(T_i_j.linear()), t_ij_(T_i_j.translation()) {
  q_ij_.normalize();
  // S = D^1/2 V^T from information = V D V^T, so ||S e||^2 = e^T information e. Unlike a
  // Cholesky factor it exists for semi-definite information too (negative round-off clamped).
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(0.5 *
                                                      (information + information.transpose()));
  sqrt_info_ =
      eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace hydra_multi
