#include "hydra_multi/backend/mesh_deformation.h"

#include <algorithm>
#include <cmath>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {

void deformMesh(std::vector<MeshVertex>& vertices, const std::vector<Eigen::Isometry3d>& initial,
                const std::vector<Eigen::Isometry3d>& optimized,
                const std::vector<int64_t>& times_ns, double window_s, size_t k) {
  if (initial.empty() || initial.size() != optimized.size() || initial.size() != times_ns.size() ||
      k == 0)
    return;
  std::vector<Eigen::Vector3d> centres;
  std::vector<Eigen::Vector3f> positions;
  for (const Eigen::Isometry3d& T : initial) centres.push_back(T.translation());
  for (const MeshVertex& v : vertices) positions.push_back(v.position);
  MeshBinding binding;
  bindMesh(binding, vertices, centres, times_ns, window_s, k);
  const std::vector<Eigen::Vector3f> moved = blendMesh(binding, positions, initial, optimized);
  for (size_t i = 0; i < vertices.size(); ++i) vertices[i].position = moved[i];
}

void bindMesh(MeshBinding& binding, const std::vector<MeshVertex>& vertices,
              const std::vector<Eigen::Vector3d>& positions, const std::vector<int64_t>& times_ns,
              double window_s, size_t k) {
  k = std::min<size_t>(k, 255);
  const int64_t window = windowNs(window_s);
  // What of the earlier binding holds: its control points, unless one changed or the options did.
  size_t kept_points = std::min(binding.control_points.size(), positions.size());
  if (binding.k != k || binding.window_s != window_s || kept_points < binding.control_points.size())
    kept_points = 0;
  for (size_t c = 0; c < kept_points; ++c) {
    if (binding.control_points[c] != positions[c] ||
        binding.control_point_times[c] != times_ns[c]) {
      kept_points = 0;
      break;
    }
  }
  std::vector<int64_t> new_times(times_ns.begin() + static_cast<std::ptrdiff_t>(kept_points),
                                 times_ns.end());
  std::sort(new_times.begin(), new_times.end());
  const bool any_new = !new_times.empty();
  // A vertex bound before keeps its binding unless a new control point may be among its nearest.
  const auto holds = [&](size_t i) {
    if (kept_points == 0 || i >= binding.vertices.size() || !(binding.vertices[i] == vertices[i]))
      return false;
    if (!any_new) return true;
    if (window <= 0 || binding.window_moved[i]) return false;
    const int64_t t = vertices[i].time_ns;
    const auto first = std::lower_bound(new_times.begin(), new_times.end(), t - window);
    return first == new_times.end() || *first > t + window;
  };
  // Kept bindings stay where they are (a vertex keeps its index); the others are bound below.
  const size_t n = vertices.size();
  std::vector<uint8_t> rebind(n, 0);
  binding.bound = 0;
  for (size_t i = 0; i < n; ++i) {
    rebind[i] = !holds(i);
    binding.bound += rebind[i];
  }
  binding.neighbours.resize(n * k);
  binding.weights.resize(n * k);
  binding.count.resize(n);
  binding.window_moved.resize(n);
  for (size_t i = 0; i < n; ++i) {
    if (rebind[i]) binding.count[i] = binding.window_moved[i] = 0;  // none until bound below
  }
  if (binding.bound > 0 && !positions.empty() && k > 0) {
    const TimedNeighbors index(positions, times_ns, window);
    std::vector<int64_t> sorted_times = times_ns;
    std::sort(sorted_times.begin(), sorted_times.end());
    for (size_t i = 0; i < n; ++i) {
      if (!rebind[i]) continue;
      const Eigen::Vector3d v = vertices[i].position.cast<double>();
      const int64_t t = vertices[i].time_ns;
      const auto nearest = index.nearest(v, t, k + 1);
      // d_max: the (k+1)-th neighbour's distance, so the k nearest all weigh more than zero.
      const double d_max =
          nearest.size() > k ? nearest[k].distance : nearest.back().distance * 1.01 + 1e-9;
      double total = 0.0;
      const size_t m = std::min(nearest.size(), k);
      for (size_t j = 0; j < m; ++j) {
        const double w = std::max(1e-9, 1.0 - nearest[j].distance / std::max(d_max, 1e-9));
        binding.neighbours[i * k + j] = static_cast<uint32_t>(nearest[j].index);
        binding.weights[i * k + j] = w;
        total += w;
      }
      for (size_t j = 0; j < m; ++j) binding.weights[i * k + j] /= total;
      binding.count[i] = static_cast<uint8_t>(m);
      if (window > 0) {
        const auto first = std::lower_bound(sorted_times.begin(), sorted_times.end(), t - window);
        binding.window_moved[i] = first == sorted_times.end() || *first > t + window;
      }
    }
  }
  // Vertices whose binding changed are blended again.
  if (binding.blended.size() > n) binding.blended.resize(n);
  for (size_t i = 0; i < n && i < binding.blended.size(); ++i) {
    if (rebind[i]) binding.blended[i] = Eigen::Vector3f::Constant(std::nanf(""));
  }
  binding.k = k;
  binding.window_s = window_s;
  binding.control_points = positions;
  binding.control_point_times = times_ns;
  binding.vertices = vertices;
}

std::vector<Eigen::Vector3f> blendMesh(MeshBinding& binding,
                                       const std::vector<Eigen::Vector3f>& aligned,
                                       const std::vector<Eigen::Isometry3d>& initial,
                                       const std::vector<Eigen::Isometry3d>& optimized) {
  const size_t n = binding.count.size(), k = binding.k;
  const size_t points = std::min(initial.size(), optimized.size());
  // Per control point, its motion v -> R (v - g) + t as A v + b, and whether it is the last
  // blend's.
  std::vector<Eigen::Matrix3d> A(points);
  std::vector<Eigen::Vector3d> b(points);
  std::vector<uint8_t> same(points, 0);
  for (size_t c = 0; c < points; ++c) {
    A[c] = optimized[c].linear() * initial[c].linear().transpose();
    b[c] = optimized[c].translation() - A[c] * initial[c].translation();
    same[c] = c < binding.blended_initial.size() &&
              binding.blended_initial[c].matrix() == initial[c].matrix() &&
              binding.blended_optimized[c].matrix() == optimized[c].matrix();
  }
  std::vector<Eigen::Vector3f> moved(n);
  binding.reblended = 0;
  for (size_t i = 0; i < n; ++i) {
    const size_t m = binding.count[i];
    bool reuse = i < binding.blended.size() && !std::isnan(binding.blended[i].x()) && m > 0;
    for (size_t j = 0; j < m && reuse; ++j) {
      const uint32_t c = binding.neighbours[i * k + j];
      reuse = c < points && same[c];
    }
    if (reuse) {
      moved[i] = binding.blended[i];
      continue;
    }
    ++binding.reblended;
    const Eigen::Vector3d v = aligned[i].cast<double>();
    if (m == 0) {
      moved[i] = aligned[i];
      continue;
    }
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t j = 0; j < m; ++j) {
      const uint32_t c = binding.neighbours[i * k + j];
      sum += binding.weights[i * k + j] * (A[c] * v + b[c]);
    }
    moved[i] = sum.cast<float>();
  }
  binding.blended_initial.assign(initial.begin(),
                                 initial.begin() + static_cast<std::ptrdiff_t>(points));
  binding.blended_optimized.assign(optimized.begin(),
                                   optimized.begin() + static_cast<std::ptrdiff_t>(points));
  binding.blended = moved;
  return moved;
}

}  // namespace hydra_multi
