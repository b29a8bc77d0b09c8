#pragma once
// SO(3) and SE(3) on Eigen.
//
// NOTATION (used everywhere in the project): T_a_b maps points from frame b to frame a, so
// T_a_c = T_a_b * T_b_c and p_a = T_a_b * p_b. A tangent vector of SE(3) is xi = [rho; phi]:
// translation part first, rotation part second (the order of g2o's information matrices).
//
// Derivation, written once. With theta = |phi| and K = hat(phi / theta):
//   exp_SO3(phi) = I + sin(theta) K + (1 - cos(theta)) K^2                       (Rodrigues)
//   exp_SE3(xi)  = [exp_SO3(phi), V(phi) rho],
//   V(phi)       = I + (1 - cos(theta)) / theta^2 hat(phi) + (theta - sin(theta)) / theta^3
//   hat(phi)^2 V(phi)^-1    = I - 1/2 hat(phi) + (1/theta^2 - cot(theta/2) / (2 theta)) hat(phi)^2
// Near theta = 0 the coefficients use their Taylor series (1/2, 1/6 and 1/12 + theta^2/720).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace hydra_multi {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The information matrix (inverse covariance) of independent noise of these variances on each
/// translation axis and each rotation axis, in the [rho; phi] order (translation first).
Matrix6d informationFromVariances(double translation_variance, double rotation_variance);

/// The skew-symmetric matrix with hat(w) * v = w x v.
Eigen::Matrix3d hat(const Eigen::Vector3d& w);

/// Rotation by the angle-axis vector phi (angle |phi| about phi / |phi|).
Eigen::Matrix3d expSO3(const Eigen::Vector3d& phi);
/// The angle-axis vector of a rotation, with angle in [0, pi].
Eigen::Vector3d logSO3(const Eigen::Matrix3d& R);

/// exp of xi = [rho; phi] (translation first).
Eigen::Isometry3d expSE3(const Vector6d& xi);
/// log of a rigid transform as [rho; phi] (translation first).
Vector6d logSE3(const Eigen::Isometry3d& T);

/// T_a_b^-1 * T_a_c = T_b_c: the pose of c in the frame of b.
Eigen::Isometry3d relativePose(const Eigen::Isometry3d& T_a_b, const Eigen::Isometry3d& T_a_c);

/// Geodesic interpolation: T_a * exp(s * log(T_a^-1 * T_b)); s = 0 gives T_a, s = 1 gives T_b.
Eigen::Isometry3d interpolate(const Eigen::Isometry3d& T_a, const Eigen::Isometry3d& T_b, double s);

/// Projects a 3x3 matrix to the nearest rotation (Frobenius norm), through the SVD.
Eigen::Matrix3d projectToSO3(const Eigen::Matrix3d& M);

/// A similarity transform: p_dst = scale * R * p_src + t.
struct Similarity3 {
  Eigen::Isometry3d T_dst_src = Eigen::Isometry3d::Identity();
  double scale = 1.0;
};

/// Least-squares alignment of corresponding points (Umeyama 1991): the transform that maps src onto
/// dst, with or without scale. nullopt with fewer than 3 points, a size mismatch, non-finite
/// coordinates or a degenerate (collinear) configuration.
std::optional<Similarity3> umeyamaAlignment(const Eigen::Matrix3Xd& src,
                                            const Eigen::Matrix3Xd& dst, bool with_scale);

}  // namespace hydra_multi
