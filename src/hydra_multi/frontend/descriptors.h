#pragma once
// Keyframe descriptors for loop-closure detection (paper III-A; Hydra's descriptors). A keyframe is
// rooted at its parent place; its neighbourhood is the places reachable from there over the
// places graph within `radius` metres of path (Dijkstra over place-place edges, Euclidean
// lengths), and the objects whose parent place is in it:
//   places   histogram of the neighbourhood's place radii (`place_bins` bins over
//            [place_min, place_max] m, values outside clamped to the end bins);
//   objects  histogram of the neighbourhood's object labels;
//   visual   the robot's bag-of-words vector of the keyframe.
// Every histogram is L1-normalized; the score of two is 1 - L1/2 in [0, 1] (1: identical).

#include <map>
#include <optional>
#include <vector>

#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct DescriptorOptions {
  double radius = 13.0;  ///< m along the places graph (Hydra)
  int place_bins = 30;   ///< Hydra: 30 bins over 0.5-2.5 m
  double place_min = 0.5;
  double place_max = 2.5;
};

/// A sparse L1-normalized histogram: (bin or label, weight), by increasing bin.
using Histogram = std::vector<std::pair<uint32_t, double>>;

/// 1 - half the L1 distance of two normalized histograms: 1 identical, 0 disjoint.
double histogramScore(const Histogram& a, const Histogram& b);

struct KeyframeDescriptors {
  NodeId keyframe;
  std::optional<NodeId> root;            ///< the parent place
  std::vector<NodeId> places, objects;   ///< the neighbourhood
  Histogram place_radii, object_labels;  ///< empty when the neighbourhood has none
  Histogram bow;                         ///< empty without a visual descriptor
};

/// The descriptors of a keyframe of `graph`; `visual` may be null.
KeyframeDescriptors describeKeyframe(const SceneGraph& graph, NodeId keyframe,
                                     const KeyframeDescriptor* visual,
                                     const DescriptorOptions& options = {});

}  // namespace hydra_multi
