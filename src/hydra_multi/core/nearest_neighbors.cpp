#include "hydra_multi/core/nearest_neighbors.h"

#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <stdexcept>
#include <string>

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

TimedNeighbors::TimedNeighbors(const std::vector<Eigen::Vector3d>& points,
                               const std::vector<int64_t>& times_ns, int64_t window_ns)
    : window_ns_(window_ns) {
  if (points.size() != times_ns.size())
    throw std::invalid_argument("TimedNeighbors: " + std::to_string(points.size()) +
                                " points but " + std::to_string(times_ns.size()) + " times");
  if (window_ns_ <= 0) {
    all_ = std::make_unique<NearestNeighbors>(points);
    return;
  }
  index_.resize(points.size());
  for (size_t i = 0; i < index_.size(); ++i) index_[i] = i;
  std::stable_sort(index_.begin(), index_.end(),
                   [&](size_t a, size_t b) { return times_ns[a] < times_ns[b]; });
  for (const size_t i : index_) {
    points_.push_back(points[i]);
    times_.push_back(times_ns[i]);
  }
}

TimedNeighbors::~TimedNeighbors() = default;

size_t TimedNeighbors::size() const { return all_ ? all_->size() : points_.size(); }

std::vector<NearestNeighbors::Neighbor> TimedNeighbors::nearest(const Eigen::Vector3d& query,
                                                                int64_t time_ns, size_t k) const {
  if (all_) return all_->nearest(query, k);
  if (times_.empty() || k == 0) return {};
  auto first = std::lower_bound(times_.begin(), times_.end(), time_ns - window_ns_);
  auto last = std::upper_bound(times_.begin(), times_.end(), time_ns + window_ns_);
  if (first == last) {
    // None made within the window: centre it on the nearest time at which some were made.
    const auto after = std::lower_bound(times_.begin(), times_.end(), time_ns);
    int64_t centre = 0;
    if (after == times_.end()) {
      centre = times_.back();
    } else if (after == times_.begin()) {
      centre = *after;
    } else {
      centre = (*after - time_ns) < (time_ns - *(after - 1)) ? *after : *(after - 1);
    }
    first = std::lower_bound(times_.begin(), times_.end(), centre - window_ns_);
    last = std::upper_bound(times_.begin(), times_.end(), centre + window_ns_);
  }
  std::vector<NearestNeighbors::Neighbor> candidates;
  for (auto it = first; it != last; ++it) {
    const size_t i = static_cast<size_t>(it - times_.begin());
    candidates.push_back({index_[i], (points_[i] - query).norm()});
  }
  const auto closer = [](const NearestNeighbors::Neighbor& a, const NearestNeighbors::Neighbor& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.index < b.index);
  };
  k = std::min(k, candidates.size());
  std::partial_sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(k),
                    candidates.end(), closer);
  candidates.resize(k);
  return candidates;
}

}  // namespace hydra_multi
