#include "hydra_multi/registration/closed_form.h"

#include <Eigen/SVD>

namespace hydra_multi {

std::optional<Eigen::Isometry3d> weightedRigidAlignment(const std::vector<Eigen::Vector3d>& src,
                                                        const std::vector<Eigen::Vector3d>& dst,
                                                        const std::vector<double>& weights) {
  if (src.size() != dst.size() || (!weights.empty() && weights.size() != src.size()))
    return std::nullopt;
  double total = 0.0;
  size_t used = 0;
  Eigen::Vector3d mean_src = Eigen::Vector3d::Zero(), mean_dst = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < src.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!(w > 0.0)) continue;
    total += w;
    ++used;
    mean_src += w * src[i];
    mean_dst += w * dst[i];
  }
  if (used < 3) return std::nullopt;
  mean_src /= total;
  mean_dst /= total;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < src.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    if (w > 0.0) covariance += w * (dst[i] - mean_dst) * (src[i] - mean_src).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  // Collinear (or coincident) points leave the rotation about their line undetermined.
  const Eigen::Vector3d s = svd.singularValues();
  if (!(s(1) > 1e-9 * std::max(1.0, s(0)))) return std::nullopt;
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1.0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = svd.matrixU() * D * svd.matrixV().transpose();
  T.translation() = mean_dst - T.linear() * mean_src;
  if (!T.matrix().allFinite()) return std::nullopt;
  return T;
}

}  // namespace hydra_multi
