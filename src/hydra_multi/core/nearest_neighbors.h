#pragma once
// Nearest neighbours among 3D points: a KD-tree (nanoflann) built once over a fixed set of points;
// and among points stamped with the time they were made, within a window of a query time.

#include <Eigen/Core>
#include <cstdint>
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

/// Nearest neighbours among points stamped with the time a robot made them, counting only those
/// made within a window of the query's time. A robot's map holds the drift between two passes
/// over one place, so what it made on another pass is no neighbour of what it makes now, however
/// close the two lie in its map. Where it made none within the window, the window moves to the
/// time nearest the query's at which it made some.
class TimedNeighbors {
 public:
  /// `window_ns` <= 0: no window, every point counts (plain nearest neighbours).
  TimedNeighbors(const std::vector<Eigen::Vector3d>& points, const std::vector<int64_t>& times_ns,
                 int64_t window_ns);
  ~TimedNeighbors();
  TimedNeighbors(const TimedNeighbors&) = delete;
  TimedNeighbors& operator=(const TimedNeighbors&) = delete;

  /// The k nearest points made within the window of `time_ns`, nearest first (fewer when the
  /// window holds fewer; none only when there are no points).
  std::vector<NearestNeighbors::Neighbor> nearest(const Eigen::Vector3d& query, int64_t time_ns,
                                                  size_t k = 1) const;
  size_t size() const;

 private:
  std::vector<Eigen::Vector3d> points_;
  std::vector<int64_t> times_;  // ascending
  std::vector<size_t> index_;   // the caller's index of each point, in time order
  int64_t window_ns_;
  std::unique_ptr<NearestNeighbors> all_;  // without a window
};

}  // namespace hydra_multi
