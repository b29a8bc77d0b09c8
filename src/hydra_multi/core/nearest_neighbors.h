#pragma once
// Nearest neighbours among 3D points: a KD-tree (nanoflann) built once over a fixed set of points.

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace hydra_multi {

class NearestNeighbors {
 public:
  /// Indexes the points (copied). An empty set is allowed: every query then finds nothing.
  explicit NearestNeighbors(const std::vector<Eigen::Vector3d>& points);
  ~NearestNeighbors();
  NearestNeighbors(const NearestNeighbors&) = delete;
  NearestNeighbors& operator=(const NearestNeighbors&) = delete;

  struct Neighbor {
    size_t index = 0;
    double distance = 0.0;
  };
  /// The k nearest points, nearest first (fewer when the set is smaller).
  std::vector<Neighbor> nearest(const Eigen::Vector3d& query, size_t k = 1) const;
  /// Every point within `radius` of the query, by increasing index (deterministic order).
  std::vector<Neighbor> withinRadius(const Eigen::Vector3d& query, double radius) const;
  size_t size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi
