#include "hydra_multi/registration/icp.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "hydra_multi/core/nearest_neighbors.h"
#include "hydra_multi/registration/closed_form.h"

namespace hydra_multi {
namespace {

// Normal of every target point: the direction of least variance of its neighbourhood.
std::vector<Eigen::Vector3d> estimateNormals(const std::vector<Eigen::Vector3d>& points,
                                             const NearestNeighbors& index, size_t k) {
  std::vector<Eigen::Vector3d> normals(points.size(), Eigen::Vector3d::UnitZ());
  for (size_t i = 0; i < points.size(); ++i) {
    const auto neighbours = index.nearest(points[i], std::max<size_t>(3, k));
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& n : neighbours) mean += points[n.index];
    mean /= double(neighbours.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const auto& n : neighbours) {
      const Eigen::Vector3d d = points[n.index] - mean;
      covariance += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    normals[i] = solver.eigenvectors().col(0);  // smallest eigenvalue first
  }
  return normals;
}

}  // namespace

Result<IcpResult> icp(const std::vector<Eigen::Vector3d>& source,
                      const std::vector<Eigen::Vector3d>& target, const Eigen::Isometry3d& initial,
                      const IcpOptions& options) {
  if (source.size() < options.min_correspondences || target.size() < options.min_correspondences)
    return Error{"icp: " + std::to_string(source.size()) + " source and " +
                 std::to_string(target.size()) + " target points, fewer than " +
                 std::to_string(options.min_correspondences)};
  const NearestNeighbors index(target);
  const bool to_plane = options.metric == IcpOptions::Metric::kPointToPlane;
  const std::vector<Eigen::Vector3d> normals =
      to_plane ? estimateNormals(target, index, options.normal_neighbors)
               : std::vector<Eigen::Vector3d>();
  IcpResult result;
  Eigen::Isometry3d T = initial;
  std::vector<size_t> paired_source, paired_target;
  const auto pair = [&] {
    paired_source.clear();
    paired_target.clear();
    for (size_t i = 0; i < source.size(); ++i) {
      const auto nearest = index.nearest(T * source[i], 1);
      if (!nearest.empty() && nearest.front().distance <= options.max_correspondence_distance) {
        paired_source.push_back(i);
        paired_target.push_back(nearest.front().index);
      }
    }
    return paired_source.size() >= options.min_correspondences;
  };
  for (result.iterations = 0; result.iterations < options.max_iterations; ++result.iterations) {
    if (!pair())
      return Error{"icp: only " + std::to_string(paired_source.size()) + " points within " +
                   std::to_string(options.max_correspondence_distance) + " m of the target"};
    Eigen::Isometry3d next = T;
    if (to_plane) {
      // Linearized about the paired target points' centroid c, not the origin: far from the
      // origin the lever arm p x n would make the rotation ill-conditioned.
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (const size_t t : paired_target) c += target[t];
      c /= static_cast<double>(paired_target.size());
      Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
      for (size_t k = 0; k < paired_source.size(); ++k) {
        const Eigen::Vector3d p = T * source[paired_source[k]];
        const Eigen::Vector3d& q = target[paired_target[k]];
        const Eigen::Vector3d& n = normals[paired_target[k]];
        Eigen::Matrix<double, 6, 1> J;
        J << n, (p - c).cross(n);  // d r / d [t; omega], rotation about c
        const double r = n.dot(p - q);
        H += J * J.transpose();
        g += J * r;
      }
      // Directions the planes leave free (a flat top slides along itself) get no step: a light
      // damping keeps them at zero instead of a huge solve of a near-singular system.
      H.diagonal().array() += 1e-6 * H.trace() / 6.0 + 1e-12;
      const Eigen::Matrix<double, 6, 1> delta = -H.ldlt().solve(g);
      if (!delta.allFinite()) return Error{"icp: the point-to-plane system is singular"};
      const Eigen::Vector3d omega = delta.tail<3>();
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      if (omega.norm() > 0)
        R = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
      // p -> R (p - c) + c + t
      Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
      step.linear() = R;
      step.translation() = c - R * c + delta.head<3>();
      next = step * T;
    } else {
      std::vector<Eigen::Vector3d> src, dst;
      for (size_t k = 0; k < paired_source.size(); ++k) {
        src.push_back(source[paired_source[k]]);
        dst.push_back(target[paired_target[k]]);
      }
      const auto fit = weightedRigidAlignment(src, dst);
      if (!fit) return Error{"icp: the paired points are degenerate (collinear)"};
      next = *fit;
    }
    const Eigen::Isometry3d change = next * T.inverse();
    T = next;
    const double rotation = Eigen::AngleAxisd(change.linear()).angle();
    if (change.translation().norm() < options.translation_tolerance &&
        rotation < options.rotation_tolerance) {
      result.converged = true;
      ++result.iterations;
      break;
    }
  }
  if (!pair()) return Error{"icp: lost the target at the end"};
  result.T_target_source = T;
  result.inliers = paired_source;
  double sum = 0.0;
  for (size_t k = 0; k < paired_source.size(); ++k)
    sum += (T * source[paired_source[k]] - target[paired_target[k]]).squaredNorm();
  result.rmse = std::sqrt(sum / double(paired_source.size()));
  return result;
}

}  // namespace hydra_multi
