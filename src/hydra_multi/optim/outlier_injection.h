#pragma once
// Outlier loop closures for robustness benchmarks: each joins two random non-consecutive poses
// with a uniformly random rotation and a translation uniform in the bounding box of the poses,
// with the information of a typical loop closure of the graph (the one of median trace).

#include <cstdint>
#include <map>

#include "hydra_multi/optim/pose_graph.h"

namespace hydra_multi {

/// Appends outliers so that they make up `fraction` of all loop closures afterwards
/// (n = round(fraction * L / (1 - fraction)) for L loop closures); returns how many. `poses` gives
/// the nodes to join and the bounding box; deterministic from `seed`.
size_t injectOutliers(PoseGraph& graph, const std::map<NodeId, Eigen::Isometry3d>& poses,
                      double fraction, uint64_t seed);

}  // namespace hydra_multi
