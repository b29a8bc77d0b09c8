#include "hydra_multi/backend/room_segmentation.h"

#include <algorithm>
#include <map>
#include <queue>
#include <set>

namespace hydra_multi {
namespace {

double radius(const SceneGraph& graph, NodeId place) {
  return graph.getNode(place).find<PlaceAttributes>()->distance;
}

// Connected components of the places above the threshold, joined by edges above it.
std::vector<std::vector<NodeId>> components(const SceneGraph& graph,
                                            const std::vector<NodeId>& places, double threshold) {
  std::set<NodeId> kept;
  for (const NodeId p : places) {
    if (radius(graph, p) > threshold) kept.insert(p);
  }
  std::set<NodeId> visited;
  std::vector<std::vector<NodeId>> result;
  for (const NodeId start : kept) {
    if (visited.count(start)) continue;
    std::vector<NodeId> component;
    std::vector<NodeId> stack = {start};
    visited.insert(start);
    while (!stack.empty()) {
      const NodeId p = stack.back();
      stack.pop_back();
      component.push_back(p);
      for (const NodeId q : graph.neighbours(p)) {
        if (!kept.count(q) || visited.count(q)) continue;
        const EdgeAttributes* edge = graph.findEdge(p, q);
        if (edge == nullptr || (edge->weighted && edge->weight <= threshold)) continue;
        visited.insert(q);
        stack.push_back(q);
      }
    }
    std::sort(component.begin(), component.end());
    result.push_back(std::move(component));
  }
  return result;
}

}  // namespace

RoomSegmentation segmentRooms(const SceneGraph& graph, const RoomSegmentationOptions& options) {
  RoomSegmentation segmentation;
  const std::vector<NodeId> places = graph.nodesInLayer(Layer::kPlaces);
  if (places.empty() || options.thresholds < 1) return segmentation;
  std::vector<std::vector<std::vector<NodeId>>> seeds;
  std::vector<double> thresholds;
  for (int i = 0; i < options.thresholds; ++i) {
    const double t = options.thresholds == 1
                         ? options.min_threshold
                         : options.min_threshold + (options.max_threshold - options.min_threshold) *
                                                       i / (options.thresholds - 1);
    std::vector<std::vector<NodeId>> big;
    for (auto& c : components(graph, places, t)) {
      if (c.size() >= options.min_room_places) big.push_back(std::move(c));
    }
    thresholds.push_back(t);
    segmentation.seeds_per_threshold.push_back(big.size());
    seeds.push_back(std::move(big));
  }
  std::vector<size_t> counts = segmentation.seeds_per_threshold;
  std::sort(counts.begin(), counts.end());
  const size_t wanted = options.rule == RoomSegmentationOptions::Rule::kMost
                            ? counts.back()
                            : counts[(counts.size() - 1) / 2];
  size_t chosen = 0;
  while (segmentation.seeds_per_threshold[chosen] != wanted) ++chosen;
  segmentation.threshold = thresholds[chosen];
  const auto& room_seeds = seeds[chosen];
  if (room_seeds.empty()) return segmentation;

  // Grow: Dijkstra from every seed at once over the places graph.
  std::map<NodeId, std::pair<double, size_t>> best;  // place -> (distance, room)
  using Item = std::pair<double, std::pair<NodeId, size_t>>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t r = 0; r < room_seeds.size(); ++r) {
    for (const NodeId p : room_seeds[r]) {
      best[p] = {0.0, r};
      queue.push({0.0, {p, r}});
    }
  }
  while (!queue.empty()) {
    const auto [d, item] = queue.top();
    queue.pop();
    const auto [p, r] = item;
    if (best[p].first < d || best[p].second != r) continue;
    const Eigen::Vector3d& from = graph.getNode(p).position;
    for (const NodeId q : graph.neighbours(p)) {
      const Node& n = graph.getNode(q);
      if (n.layer() != Layer::kPlaces) continue;
      const double through = d + (n.position - from).norm();
      const auto known = best.find(q);
      if (known == best.end() || through < known->second.first) {
        best[q] = {through, r};
        queue.push({through, {q, r}});
      }
    }
  }
  // Join rooms that an opening wider than a door connects (union-find over the rooms).
  std::vector<size_t> parent(room_seeds.size());
  for (size_t r = 0; r < parent.size(); ++r) parent[r] = r;
  const auto find = [&parent](size_t r) {
    while (parent[r] != r) r = parent[r] = parent[parent[r]];
    return r;
  };
  if (options.max_door_radius > 0.0) {
    for (const auto& [p, entry] : best) {
      for (const NodeId q : graph.neighbours(p)) {
        const auto other = best.find(q);
        if (other == best.end() || other->second.second == entry.second) continue;
        const EdgeAttributes* edge = graph.findEdge(p, q);
        // An unweighted edge says nothing of the opening's width.
        if (edge == nullptr || !edge->weighted || edge->weight <= options.max_door_radius) continue;
        parent[find(entry.second)] = find(other->second.second);
      }
    }
  }
  std::map<size_t, size_t> index_of_root;
  for (size_t r = 0; r < parent.size(); ++r)
    index_of_root.try_emplace(find(r), index_of_root.size());
  segmentation.rooms.assign(index_of_root.size(), {});
  for (const auto& [place, entry] : best)
    segmentation.rooms[index_of_root.at(find(entry.second))].push_back(place);
  for (auto& room : segmentation.rooms) std::sort(room.begin(), room.end());
  return segmentation;
}

void applyRooms(SceneGraph& graph, const RoomSegmentation& segmentation) {
  for (const Layer layer : {Layer::kRooms, Layer::kBuildings}) {
    for (const NodeId id : graph.nodesInLayer(layer)) graph.removeNode(id);
  }
  if (segmentation.rooms.empty()) return;
  Eigen::Vector3d building_position = Eigen::Vector3d::Zero();
  for (size_t r = 0; r < segmentation.rooms.size(); ++r) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const NodeId p : segmentation.rooms[r]) mean += graph.getNode(p).position;
    mean /= double(segmentation.rooms[r].size());
    Node room = makeNode(NodeId('R', r), Layer::kRooms, mean);
    room.semantic()->name = "room " + std::to_string(r);
    graph.addOrUpdateNode(room);
    for (const NodeId p : segmentation.rooms[r]) graph.addOrUpdateEdge(room.id, p);
    building_position += mean;
  }
  building_position /= double(segmentation.rooms.size());
  Node building = makeNode(NodeId('B', 0), Layer::kBuildings, building_position);
  building.semantic()->name = "building";
  graph.addOrUpdateNode(building);
  for (size_t r = 0; r < segmentation.rooms.size(); ++r)
    graph.addOrUpdateEdge(building.id, NodeId('R', r));
}

}  // namespace hydra_multi
