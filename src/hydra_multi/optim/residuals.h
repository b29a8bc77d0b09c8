#pragma once
// Ceres residuals of a relative-pose edge between poses i and j, with parameter blocks
// q_i, t_i, q_j, t_j (Eigen quaternion order x y z w on Ceres' EigenQuaternionManifold, and R^3).
//
// Chordal (the SE-Sync objective F of data/README.md, exactly):
//   r = [ sqrt(tau)   * (t_j - t_i - R_i t_ij)            (3)
//         sqrt(kappa) * vec(R_j - R_i R_ij) ]              (9)
//   with Sigma = information^-1, tau = 3 / tr(Sigma_t), kappa = 3 / (2 tr(Sigma_R)) (an
//   information that is not positive definite: its blocks' inverses, as SE-Sync's reader).
//   Ceres minimizes 1/2 sum ||r||^2 = F / 2.
//
// Geodesic (eq. (3) of the paper: ||T_i^-1 T_j boxminus E_ij||^2_Omega):
//   E   = T_ij^-1 T_i^-1 T_j,  with R_E = R_ij^T R_i^T R_j and t_E = R_ij^T (R_i^T (t_j - t_i) -
//   t_ij) e   = log(E) = [V(phi)^-1 t_E; phi],  phi = log(R_E)                  (core/se3.h
//   derivation) r   = sqrt_info * e,  sqrt_info^T sqrt_info = information.

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>

#include "hydra_multi/core/se3.h"

namespace hydra_multi {

/// tau and kappa of an edge's information matrix (data/README.md); for one that is not positive
/// definite, from its translation and rotation blocks as SE-Sync's reader takes them (those blocks
/// must be positive definite: io/g2o_format.h refuses edges whose are not).
struct IsotropicWeights {
  double kappa = 1.0;  ///< rotation
  double tau = 1.0;    ///< translation
};
IsotropicWeights isotropicWeights(const Matrix6d& information);

/// The symmetric matrix nearest `information` whose eigenvalues are all at least
/// kPositiveDefiniteFloor times its largest magnitude (eigenvalues clamped): the geodesic
/// residual's weight for an information that is not positive definite.
inline constexpr double kPositiveDefiniteFloor = 1e-6;
Matrix6d nearestPositiveDefinite(const Matrix6d& information);

class ChordalResidual {
 public:
  ChordalResidual(const Eigen::Isometry3d& T_i_j, const IsotropicWeights& weights)
      : R_ij_(T_i_j.linear()),
        t_ij_(T_i_j.translation()),
        sqrt_kappa_(std::sqrt(weights.kappa)),
        sqrt_tau_(std::sqrt(weights.tau)) {}

  template <typename T>
  bool operator()(const T* q_i_ptr, const T* t_i_ptr, const T* q_j_ptr, const T* t_j_ptr,
                  T* residual_ptr) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(q_i_ptr), q_j(q_j_ptr);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_i(t_i_ptr), t_j(t_j_ptr);
    const Eigen::Matrix<T, 3, 3> R_i = q_i.toRotationMatrix();
    const Eigen::Matrix<T, 3, 3> R_j = q_j.toRotationMatrix();
    Eigen::Map<Eigen::Matrix<T, 12, 1>> r(residual_ptr);
    r.template head<3>() = T(sqrt_tau_) * (t_j - t_i - R_i * t_ij_.cast<T>());
    const Eigen::Matrix<T, 3, 3> dR = T(sqrt_kappa_) * (R_j - R_i * R_ij_.cast<T>());
    r.template tail<9>() = Eigen::Map<const Eigen::Matrix<T, 9, 1>>(dR.data());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Isometry3d& T_i_j,
                                     const IsotropicWeights& weights) {
    return new ceres::AutoDiffCostFunction<ChordalResidual, 12, 4, 3, 4, 3>(
        new ChordalResidual(T_i_j, weights));
  }

 private:
  Eigen::Matrix3d R_ij_;
  Eigen::Vector3d t_ij_;
  double sqrt_kappa_;
  double sqrt_tau_;
};

/// S with S^T S = information (S = D^1/2 V^T): the geodesic residual's weight; an information
/// that is not positive definite is weighed by nearestPositiveDefinite.
Matrix6d geodesicSqrtInformation(const Matrix6d& information);

class GeodesicResidual {
 public:
  GeodesicResidual(const Eigen::Isometry3d& T_i_j, const Matrix6d& information);

  template <typename T>
  bool operator()(const T* q_i_ptr, const T* t_i_ptr, const T* q_j_ptr, const T* t_j_ptr,
                  T* residual_ptr) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(q_i_ptr), q_j(q_j_ptr);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_i(t_i_ptr), t_j(t_j_ptr);
    const Eigen::Quaternion<T> q_ij_inv = q_ij_.conjugate().cast<T>();
    // The error transform E = T_ij^-1 T_i^-1 T_j.
    const Eigen::Quaternion<T> q_e = q_ij_inv * q_i.conjugate() * q_j;
    const Eigen::Matrix<T, 3, 1> t_e = q_ij_inv * (q_i.conjugate() * (t_j - t_i) - t_ij_.cast<T>());
    // phi = log(R_E), through Ceres' angle-axis conversion (w first).
    const T q_wxyz[4] = {q_e.w(), q_e.x(), q_e.y(), q_e.z()};
    Eigen::Matrix<T, 3, 1> phi;
    ceres::QuaternionToAngleAxis(q_wxyz, phi.data());
    // rho = V(phi)^-1 t_E = t_E - 1/2 phi x t_E + c phi x (phi x t_E).
    const T theta_sq = phi.squaredNorm();
    T c;
    if (theta_sq < T(1e-8)) {
      c = T(1.0 / 12.0) + theta_sq / T(720.0);
    } else {
      const T theta = ceres::sqrt(theta_sq);
      const T half = T(0.5) * theta;
      c = T(1.0) / theta_sq - ceres::cos(half) / (T(2.0) * theta * ceres::sin(half));
    }
    const Eigen::Matrix<T, 3, 1> phi_x_t = phi.cross(t_e);
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = t_e - T(0.5) * phi_x_t + c * phi.cross(phi_x_t);
    e.template tail<3>() = phi;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual_ptr);
    r = sqrt_info_.cast<T>() * e;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Isometry3d& T_i_j, const Matrix6d& information) {
    return new ceres::AutoDiffCostFunction<GeodesicResidual, 6, 4, 3, 4, 3>(
        new GeodesicResidual(T_i_j, information));
  }

 private:
  Eigen::Quaterniond q_ij_;
  Eigen::Vector3d t_ij_;
  Matrix6d sqrt_info_;
};

/// The rotation manifold of the geodesic cost: q <- Exp(delta) q (left, as Ceres'
/// EigenQuaternionManifold), with PlusJacobian [I_3; 0]: a cost function on it gives its Jacobian
/// in the tangent space, in the first three columns of the quaternion's (the fourth is zero).
class LeftQuaternionTangentManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 4; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

/// GeodesicResidual with its Jacobian in closed form, in the tangent space of left perturbations
/// R <- Exp(d) R (LeftQuaternionTangentManifold; t plain R^3). With e = [rho; phi], W = V(phi)^-1,
/// Jr^-1 = I + 1/2 hat(phi) + c hat(phi)^2, c = 1/theta^2 - cot(theta/2) / (2 theta), and
/// P = d rho / d phi = 1/2 hat(t_E) + dc (phi x (phi x t_E)) phi^T + c ((phi.t_E) I + phi t_E^T -
/// 2 t_E phi^T), dc = c'(theta) / theta:
///   d phi / d_i = -Jr^-1 R_j^T          d phi / d_j = Jr^-1 R_j^T
///   d t_E / d_i = R_ij^T R_i^T hat(t_j - t_i),  d t_E / dt_i = -R_ij^T R_i^T = -d t_E / dt_j
///   d rho = W d t_E + P d phi;  r = sqrt_info e.
/// A plain value, not a Ceres cost function: the sparse solver's problems hold one per edge in one
/// array. A diagonal sqrt_info (the station's information, per axis) is kept as its diagonal: r as
/// the full matrix would give it, to the bit, and the Jacobians from their 3x3 corners (phi's rows
/// are zero in the translation's columns); any other on the heap. Checked against
/// GeodesicResidual's automatic derivatives (tests/optim/test_residuals.cpp).
class GeodesicFactor {
 public:
  GeodesicFactor(const Eigen::Isometry3d& T_i_j, const Matrix6d& information);
  /// r at poses i and j; J_i, J_j (when not null): d r / d [d_i; t_i] and d r / d [d_j; t_j].
  void evaluate(const Eigen::Quaterniond& q_i, const Eigen::Vector3d& t_i,
                const Eigen::Quaterniond& q_j, const Eigen::Vector3d& t_j, Vector6d& r,
                Matrix6d* J_i, Matrix6d* J_j) const;

 private:
  Eigen::Matrix3d R_ij_t_;  // R_ij^T
  Eigen::Vector3d t_ij_;
  Vector6d sqrt_diagonal_;                     // sqrt_info when diagonal
  std::shared_ptr<const Matrix6d> sqrt_info_;  // sqrt_info otherwise
};

/// GeodesicFactor as a Ceres cost function on LeftQuaternionTangentManifold: the tangent
/// Jacobian of a rotation in the first three columns of its quaternion's (the fourth zero).
class GeodesicCost : public ceres::SizedCostFunction<6, 4, 3, 4, 3> {
 public:
  GeodesicCost(const Eigen::Isometry3d& T_i_j, const Matrix6d& information)
      : factor_(T_i_j, information) {}
  explicit GeodesicCost(const GeodesicFactor& factor) : factor_(factor) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  GeodesicFactor factor_;
};

}  // namespace hydra_multi
