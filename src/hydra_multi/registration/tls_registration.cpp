#include "hydra_multi/registration/tls_registration.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "hydra_multi/optim/gnc.h"
#include "hydra_multi/registration/closed_form.h"
#include "hydra_multi/registration/max_clique.h"

namespace hydra_multi {
namespace {

// The distinct points of `points` (equal coordinates: one point, found by an open-addressing hash
// of the coordinates' bits), each point's number among them in order of first appearance, and
// their distances: distance[a * count + b] = ||p_a - p_b||, the same value both ways. A point
// counted twice would change no distance, only repeat one.
struct DistinctPoints {
  std::vector<size_t> index;
  size_t count = 0;
  std::vector<double> distance;
};

uint64_t hashOf(const Eigen::Vector3d& p) {
  uint64_t h = 0;
  for (int k = 0; k < 3; ++k) {
    uint64_t bits = 0;
    std::memcpy(&bits, &p[k], sizeof(bits));
    h = (h ^ bits) * 0x9e3779b97f4a7c15ull;
    h ^= h >> 29;
  }
  return h;
}

DistinctPoints distinctPoints(const std::vector<Eigen::Vector3d>& points) {
  DistinctPoints d;
  size_t slots = 16;
  while (slots < 2 * points.size()) slots *= 2;
  constexpr size_t kEmpty = std::numeric_limits<size_t>::max();
  std::vector<size_t> table(slots, kEmpty);  // per slot, the number of a distinct point
  std::vector<size_t> first;                 // per distinct point, its first index in `points`
  d.index.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    size_t slot = hashOf(points[i]) & (slots - 1);
    while (table[slot] != kEmpty && points[first[table[slot]]] != points[i])
      slot = (slot + 1) & (slots - 1);
    if (table[slot] == kEmpty) {
      table[slot] = first.size();
      first.push_back(i);
    }
    d.index[i] = table[slot];
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
