#include "hydra_multi/frontend/descriptors.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace hydra_multi {
namespace {

// Counts (bin -> count) as a normalized histogram.
Histogram normalized(const std::map<uint32_t, double>& counts) {
  double total = 0.0;
  for (const auto& [bin, weight] : counts) total += weight;
  Histogram h(counts.begin(), counts.end());
  if (total > 0.0) {
    for (auto& [bin, weight] : h) weight /= total;
  }
  return h;
}

}  // namespace

double histogramScore(const Histogram& a, const Histogram& b) {
  // For normalized histograms, 1 - L1/2 is the sum of the bin-wise minima.
  double shared = 0.0;
  auto i = a.begin();
  auto j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (i->first < j->first) {
      ++i;
    } else if (j->first < i->first) {
      ++j;
    } else {
      shared += std::min(i->second, j->second);
      ++i;
      ++j;
    }
  }
  return shared;
}

KeyframeDescriptors describeKeyframe(const SceneGraph& graph, NodeId keyframe,
                                     const KeyframeDescriptor* visual,
                                     const DescriptorOptions& options) {
  KeyframeDescriptors d;
  d.keyframe = keyframe;
  if (visual != nullptr) {
    std::map<uint32_t, double> bow;
    for (const BowEntry& e : visual->bow) bow[e.word] += e.weight;
    d.bow = normalized(bow);
  }
  d.root = graph.parent(keyframe);
  if (!d.root || graph.getNode(*d.root).layer() != Layer::kPlaces) {
    d.root.reset();
    return d;
  }
  // Dijkstra over the places graph from the root, up to `radius` metres of path.
  std::map<NodeId, double> distance = {{*d.root, 0.0}};
  using Item = std::pair<double, NodeId>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  queue.push({0.0, *d.root});
  while (!queue.empty()) {
    const auto [dist, place] = queue.top();
    queue.pop();
    if (dist > distance[place]) continue;
    const Eigen::Vector3d& p = graph.getNode(place).position;
    for (const NodeId next : graph.neighbours(place)) {
      const Node& n = graph.getNode(next);
      if (n.layer() != Layer::kPlaces) continue;
      const double through = dist + (n.position - p).norm();
      if (through > options.radius) continue;
      const auto known = distance.find(next);
      if (known == distance.end() || through < known->second) {
        distance[next] = through;
        queue.push({through, next});
      }
    }
  }
  const double width = (options.place_max - options.place_min) / options.place_bins;
  std::map<uint32_t, double> radii, labels;
  for (const auto& [place, dist] : distance) {
    d.places.push_back(place);
    const PlaceAttributes* attributes = graph.getNode(place).find<PlaceAttributes>();
    const int bin =
        std::clamp(static_cast<int>(std::floor((attributes->distance - options.place_min) / width)),
                   0, options.place_bins - 1);
    radii[static_cast<uint32_t>(bin)] += 1.0;
    for (const NodeId child : graph.children(place)) {
      const Node& object = graph.getNode(child);
      if (object.layer() != Layer::kObjects) continue;
      d.objects.push_back(child);
      labels[object.semantic()->label] += 1.0;
    }
  }
  d.place_radii = normalized(radii);
  d.object_labels = normalized(labels);
  return d;
}

}  // namespace hydra_multi
