#include "hydra_multi/eval/scene_metrics.h"

#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <tuple>

#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {
namespace {

// Share (in %) of `from` with a point of the same label in `to` within the threshold.
std::optional<double> matchedShare(const std::vector<LabelledPoint>& from,
                                   const std::vector<LabelledPoint>& to, double threshold) {
  if (from.empty()) return std::nullopt;
  std::map<uint32_t, std::vector<Eigen::Vector3d>> by_label;
  for (const LabelledPoint& p : to) by_label[p.label].push_back(p.position);
  std::map<uint32_t, std::unique_ptr<NearestNeighbors>> index;
  for (const auto& [label, points] : by_label)
    index[label] = std::make_unique<NearestNeighbors>(points);
  size_t matched = 0;
  for (const LabelledPoint& p : from) {
    const auto it = index.find(p.label);
    if (it == index.end()) continue;
    const auto nearest = it->second->nearest(p.position);
    if (!nearest.empty() && nearest.front().distance <= threshold) ++matched;
  }
  return 100.0 * static_cast<double>(matched) / static_cast<double>(from.size());
}

using VoxelSet = std::set<std::tuple<int, int, int>>;

VoxelSet toSet(const std::vector<Eigen::Vector3i>& keys) {
  VoxelSet set;
  for (const Eigen::Vector3i& k : keys) set.emplace(k.x(), k.y(), k.z());
  return set;
}

// For each room of `a`: the largest share of its voxels inside one room of `b`; their mean.
std::optional<double> meanBestOverlap(const std::vector<VoxelSet>& a,
                                      const std::vector<VoxelSet>& b) {
  if (a.empty()) return std::nullopt;
  double total = 0.0;
  for (const VoxelSet& room : a) {
    size_t best = 0;
    for (const VoxelSet& other : b) {
      size_t common = 0;
      for (const auto& voxel : room) common += other.count(voxel);
      best = std::max(best, common);
    }
    total += room.empty() ? 0.0 : static_cast<double>(best) / static_cast<double>(room.size());
  }
  return total / static_cast<double>(a.size());
}

}  // namespace

const char* toString(ObjectVerdict::Kind kind) {
  switch (kind) {
    case ObjectVerdict::Kind::kCorrect:
      return "correct";
    case ObjectVerdict::Kind::kDuplicate:
      return "duplicate";
    case ObjectVerdict::Kind::kWrongLabel:
      return "wrong_label";
    case ObjectVerdict::Kind::kMisplaced:
      return "misplaced";
  }
  return "?";
}

ObjectMetrics objectMetrics(const std::vector<LabelledPoint>& estimated,
                            const std::vector<LabelledPoint>& truth, double threshold_m) {
  ObjectMetrics metrics;
  metrics.found_pct = matchedShare(truth, estimated, threshold_m);
  metrics.correct_pct = matchedShare(estimated, truth, threshold_m);
  std::vector<Eigen::Vector3d> true_positions;
  for (const LabelledPoint& t : truth) true_positions.push_back(t.position);
  const NearestNeighbors index(true_positions);
  const auto keepNearer = [](ObjectVerdict& v, const NearestNeighbors::Neighbor& n) {
    if (v.true_index < 0 || n.distance < v.distance_m)
      v = {v.kind, static_cast<int>(n.index), n.distance};
  };
  std::set<int> matched_truth;
  for (const LabelledPoint& e : estimated) {
    const auto near = index.withinRadius(e.position, threshold_m);
    ObjectVerdict same_label, any_label;
    for (const auto& n : near) {
      keepNearer(any_label, n);
      if (truth[n.index].label == e.label) keepNearer(same_label, n);
    }
    if (same_label.true_index >= 0) {
      ++metrics.correct;
      const bool first = matched_truth.insert(same_label.true_index).second;
      if (!first) ++metrics.duplicates;
      same_label.kind = first ? ObjectVerdict::Kind::kCorrect : ObjectVerdict::Kind::kDuplicate;
      metrics.verdicts.push_back(same_label);
    } else if (any_label.true_index >= 0) {
      ++metrics.wrong_label;
      any_label.kind = ObjectVerdict::Kind::kWrongLabel;
      metrics.verdicts.push_back(any_label);
    } else {
      ++metrics.misplaced;
      metrics.verdicts.push_back({ObjectVerdict::Kind::kMisplaced, -1, 0.0});
    }
  }
  return metrics;
}

std::optional<double> placesPositionError(const std::vector<Eigen::Vector3d>& places,
                                          const std::vector<Eigen::Vector3d>& gvd_voxels) {
  if (places.empty() || gvd_voxels.empty()) return std::nullopt;
  const NearestNeighbors index(gvd_voxels);
  double total = 0.0;
  for (const Eigen::Vector3d& p : places) total += index.nearest(p).front().distance;
  return total / static_cast<double>(places.size());
}

Eigen::Vector3i voxelKey(const Eigen::Vector3d& p, double voxel_size) {
  return (p / voxel_size).array().floor().cast<int>();
}

RoomMetrics roomMetrics(const std::vector<std::vector<Eigen::Vector3i>>& estimated,
                        const std::vector<std::vector<Eigen::Vector3i>>& truth) {
  std::vector<VoxelSet> e, t;
  for (const auto& room : estimated) e.push_back(toSet(room));
  for (const auto& room : truth) t.push_back(toSet(room));
  return {meanBestOverlap(e, t), meanBestOverlap(t, e)};
}

}  // namespace hydra_multi
