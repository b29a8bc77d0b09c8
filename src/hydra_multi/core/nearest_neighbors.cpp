#include "hydra_multi/core/nearest_neighbors.h"

#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>

namespace hydra_multi {

using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using KdTree = nanoflann::KDTreeEigenMatrixAdaptor<PointMatrix, 3, nanoflann::metric_L2_Simple>;

struct NearestNeighbors::Impl {
  PointMatrix points;
  std::unique_ptr<KdTree> tree;  // refers to `points`
};

NearestNeighbors::NearestNeighbors(const std::vector<Eigen::Vector3d>& points)
    : impl_(std::make_unique<Impl>()) {
  impl_->points.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) {
    impl_->points.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  }
  if (!points.empty()) impl_->tree = std::make_unique<KdTree>(3, std::cref(impl_->points), 10);
}

NearestNeighbors::~NearestNeighbors() = default;

size_t NearestNeighbors::size() const { return static_cast<size_t>(impl_->points.rows()); }

std::vector<NearestNeighbors::Neighbor> NearestNeighbors::nearest(const Eigen::Vector3d& query,
                                                                  size_t k) const {
  if (!impl_->tree || k == 0) return {};
  k = std::min(k, size());
  std::vector<Eigen::Index> indices(k);
  std::vector<double> squared(k);
  const size_t found =
      impl_->tree->index->knnSearch(query.data(), k, indices.data(), squared.data());
  std::vector<Neighbor> result(found);
  for (size_t i = 0; i < found; ++i) {
    result[i] = {static_cast<size_t>(indices[i]), std::sqrt(squared[i])};
  }
  return result;
}

std::vector<NearestNeighbors::Neighbor> NearestNeighbors::withinRadius(const Eigen::Vector3d& query,
                                                                       double radius) const {
  if (!impl_->tree || !(radius >= 0.0)) return {};
  // nanoflann's L2_Simple metric works in squared distances.
  std::vector<std::pair<Eigen::Index, double>> matches;
  impl_->tree->index->radiusSearch(query.data(), radius * radius, matches,
                                   nanoflann::SearchParams(32, 0.0f, false));
  std::vector<Neighbor> result(matches.size());
  for (size_t i = 0; i < matches.size(); ++i) {
    result[i] = {static_cast<size_t>(matches[i].first), std::sqrt(matches[i].second)};
  }
  std::sort(result.begin(), result.end(),
            [](const Neighbor& a, const Neighbor& b) { return a.index < b.index; });
  return result;
}

}  // namespace hydra_multi
