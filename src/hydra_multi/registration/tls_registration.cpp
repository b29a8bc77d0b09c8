#include "hydra_multi/registration/tls_registration.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "hydra_multi/optim/gnc.h"
#include "hydra_multi/registration/closed_form.h"
#include "hydra_multi/registration/max_clique.h"

namespace hydra_multi {
namespace {

// The distinct points of `points` (equal coordinates: one point), each point's place among them,
// and their distances: distance[a * count + b] = ||p_a - p_b||, the same value both ways.
struct DistinctPoints {
  std::vector<size_t> index;
  size_t count = 0;
  std::vector<double> distance;
};

DistinctPoints distinctPoints(const std::vector<Eigen::Vector3d>& points) {
  DistinctPoints d;
  std::vector<size_t> order(points.size());
  std::iota(order.begin(), order.end(), size_t{0});
  const auto less = [&points](size_t a, size_t b) {
    return std::lexicographical_compare(points[a].data(), points[a].data() + 3, points[b].data(),
                                        points[b].data() + 3);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<size_t> first;  // per distinct point, an index of it in `points`
  d.index.resize(points.size());
  for (size_t k = 0; k < order.size(); ++k) {
    if (k == 0 || less(order[k - 1], order[k])) first.push_back(order[k]);
    d.index[order[k]] = first.size() - 1;
  }
  d.count = first.size();
  d.distance.assign(d.count * d.count, 0.0);
  for (size_t a = 0; a < d.count; ++a) {
    for (size_t b = a + 1; b < d.count; ++b) {
      d.distance[a * d.count + b] = d.distance[b * d.count + a] =
          (points[first[a]] - points[first[b]]).norm();
    }
  }
  return d;
}

}  // namespace

Result<RegistrationResult> tlsRegistration(const std::vector<Eigen::Vector3d>& source,
                                           const std::vector<Eigen::Vector3d>& target,
                                           const TlsRegistrationOptions& options) {
  if (source.size() != target.size())
    return Error{"tls registration: " + std::to_string(source.size()) + " source and " +
                 std::to_string(target.size()) + " target points"};
  const size_t n = source.size();
  for (size_t i = 0; i < n; ++i) {
    if (!source[i].allFinite() || !target[i].allFinite())
      return Error{"tls registration: correspondence " + std::to_string(i) +
                   " has a coordinate that is not finite"};
  }
  const size_t needed = std::max<size_t>(3, options.min_inliers);
  if (n < needed)
    return Error{"tls registration: " + std::to_string(n) + " correspondences, fewer than " +
                 std::to_string(needed)};
  // 1-2: pairwise consistency and its maximum clique. The distances between each side's
  // distinct points, computed once (every same-label pair shares its points with others).
  const DistinctPoints s = distinctPoints(source), t = distinctPoints(target);
  AdjacencyBits adjacency(n);
  for (size_t i = 0; i < n; ++i) {
    const double* ds = &s.distance[s.index[i] * s.count];
    const double* dt = &t.distance[t.index[i] * t.count];
    for (size_t j = i + 1; j < n; ++j) {
      if (std::abs(ds[s.index[j]] - dt[t.index[j]]) <= 2.0 * options.noise_bound)
        adjacency.connect(i, j);
    }
  }
  const std::vector<size_t> clique = maximumClique(adjacency, options.max_clique_steps).members;
  if (clique.size() < needed)
    return Error{"tls registration: the largest consistent set has " +
                 std::to_string(clique.size()) + " correspondences, fewer than " +
                 std::to_string(needed)};
  std::vector<Eigen::Vector3d> src, dst;
  for (const size_t i : clique) {
    src.push_back(source[i]);
    dst.push_back(target[i]);
  }
  // 3: GNC-TLS over the clique; residuals normalized by the noise bound (c = 1).
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  bool solved = false;
  const auto solve = [&](const std::vector<double>& weights) {
    WeightedSolution solution;
    if (const auto fit = weightedRigidAlignment(src, dst, weights)) {
      T = *fit;
      solved = true;
    }
    for (size_t i = 0; i < src.size(); ++i) {
      const double r2 = (T * src[i] - dst[i]).squaredNorm() / std::pow(options.noise_bound, 2);
      solution.squared_residuals.push_back(r2);
      solution.cost += (weights.empty() ? 1.0 : weights[i]) * r2;
    }
    return solution;
  };
  GncOptions gnc;
  gnc.inlier_threshold_sq = 1.0;
  const GncResult result = runGnc(src.size(), solve, gnc);
  if (!solved) return Error{"tls registration: the consistent correspondences are degenerate"};
  RegistrationResult registration;
  std::vector<Eigen::Vector3d> in_src, in_dst;
  for (size_t k = 0; k < clique.size(); ++k) {
    if (!result.inliers[k]) continue;
    registration.inliers.push_back(clique[k]);
    in_src.push_back(src[k]);
    in_dst.push_back(dst[k]);
  }
  if (registration.inliers.size() < needed)
    return Error{"tls registration: " + std::to_string(registration.inliers.size()) +
                 " inliers, fewer than " + std::to_string(needed)};
  // 4: refit on the inliers.
  const auto refit = weightedRigidAlignment(in_src, in_dst);
  if (!refit) return Error{"tls registration: the inliers are degenerate (collinear)"};
  registration.T_target_source = *refit;
  double sum = 0.0;
  for (size_t k = 0; k < in_src.size(); ++k) sum += (*refit * in_src[k] - in_dst[k]).squaredNorm();
  registration.rmse = std::sqrt(sum / double(in_src.size()));
  return registration;
}

Result<RegistrationResult> tlsRivalRegistration(const std::vector<Eigen::Vector3d>& source,
                                                const std::vector<Eigen::Vector3d>& target,
                                                const RegistrationResult& best,
                                                const TlsRegistrationOptions& options) {
  std::vector<bool> taken(source.size(), false);
  for (const size_t i : best.inliers) taken.at(i) = true;
  std::vector<size_t> rest;
  std::vector<Eigen::Vector3d> rest_source, rest_target;
  for (size_t i = 0; i < source.size(); ++i) {
    if (taken[i]) continue;
    rest.push_back(i);
    rest_source.push_back(source[i]);
    rest_target.push_back(target[i]);
  }
  auto rival = tlsRegistration(rest_source, rest_target, options);
  if (!rival) return rival;
  for (size_t& i : rival.value().inliers) i = rest[i];
  return rival;
}

}  // namespace hydra_multi
