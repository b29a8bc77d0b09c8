#include "hydra_multi/backend/room_segmentation.h"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <unordered_map>

namespace hydra_multi {
namespace {

// The places graph, by index in id order, read once for every threshold and the growth.
struct PlacesGraph {
  struct Link {
    size_t to;
    bool weighted;
    double weight;
  };
  std::vector<NodeId> ids;  // sorted
  std::vector<double> radius;
  std::vector<Eigen::Vector3d> position;
  std::vector<std::vector<Link>> links;  // each place's neighbours in the layer, in id order

  PlacesGraph(const SceneGraph& graph, std::vector<NodeId> places) : ids(std::move(places)) {
    std::unordered_map<NodeId, size_t> index;
    index.reserve(ids.size());
    for (size_t i = 0; i < ids.size(); ++i) index.emplace(ids[i], i);
    radius.resize(ids.size());
    position.resize(ids.size());
    links.resize(ids.size());
    for (size_t i = 0; i < ids.size(); ++i) {
      const Node& node = graph.getNode(ids[i]);
      radius[i] = node.find<PlaceAttributes>()->distance;
      position[i] = node.position;
      for (const NodeId q : graph.neighbours(ids[i])) {
        const auto j = index.find(q);
        if (j == index.end()) continue;
        const EdgeAttributes* edge = graph.findEdge(ids[i], q);
        links[i].push_back({j->second, edge->weighted, edge->weight});
      }
    }
  }
};

// Connected components of the places above the threshold, joined by edges above it, as indices;
// each component sorted, the components in the order of their first place.
std::vector<std::vector<size_t>> components(const PlacesGraph& places, double threshold) {
  const size_t n = places.ids.size();
  std::vector<bool> kept(n), visited(n, false);
  for (size_t i = 0; i < n; ++i) kept[i] = places.radius[i] > threshold;
  std::vector<std::vector<size_t>> result;
  std::vector<size_t> stack;
  for (size_t start = 0; start < n; ++start) {
    if (!kept[start] || visited[start]) continue;
    std::vector<size_t> component;
    stack.assign(1, start);
    visited[start] = true;
    while (!stack.empty()) {
      const size_t p = stack.back();
      stack.pop_back();
      component.push_back(p);
      for (const PlacesGraph::Link& link : places.links[p]) {
        if (!kept[link.to] || visited[link.to]) continue;
        if (link.weighted && link.weight <= threshold) continue;
        visited[link.to] = true;
        stack.push_back(link.to);
      }
    }
    std::sort(component.begin(), component.end());  // index order is id order
    result.push_back(std::move(component));
  }
  return result;
}

}  // namespace

RoomSegmentation segmentRooms(const SceneGraph& graph, const RoomSegmentationOptions& options) {
  RoomSegmentation segmentation;
  std::vector<NodeId> place_ids = graph.nodesInLayer(Layer::kPlaces);
  if (place_ids.empty() || options.thresholds < 1) return segmentation;
  const PlacesGraph places(graph, std::move(place_ids));
  std::vector<std::vector<std::vector<size_t>>> seeds;
  std::vector<double> thresholds;
  for (int i = 0; i < options.thresholds; ++i) {
    const double t = options.thresholds == 1
                         ? options.min_threshold
                         : options.min_threshold + (options.max_threshold - options.min_threshold) *
                                                       i / (options.thresholds - 1);
    std::vector<std::vector<size_t>> big;
    for (auto& c : components(places, t)) {
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

  // Grow: Dijkstra from every seed at once over the places graph (ties broken by id order).
  const size_t n = places.ids.size();
  constexpr size_t kNone = std::numeric_limits<size_t>::max();
  std::vector<std::pair<double, size_t>> best(n, {0.0, kNone});  // place -> (distance, room)
  using Item = std::pair<double, std::pair<size_t, size_t>>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (size_t r = 0; r < room_seeds.size(); ++r) {
    for (const size_t p : room_seeds[r]) {
      best[p] = {0.0, r};
      queue.push({0.0, {p, r}});
    }
  }
  while (!queue.empty()) {
    const auto [d, item] = queue.top();
    queue.pop();
    const auto [p, r] = item;
    if (best[p].first < d || best[p].second != r) continue;
    for (const PlacesGraph::Link& link : places.links[p]) {
      const double through = d + (places.position[link.to] - places.position[p]).norm();
      if (best[link.to].second == kNone || through < best[link.to].first) {
        best[link.to] = {through, r};
        queue.push({through, {link.to, r}});
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
    for (size_t p = 0; p < n; ++p) {
      if (best[p].second == kNone) continue;
      for (const PlacesGraph::Link& link : places.links[p]) {
        const size_t other = best[link.to].second;
        if (other == kNone || other == best[p].second) continue;
        // An unweighted edge says nothing of the opening's width.
        if (!link.weighted || link.weight <= options.max_door_radius) continue;
        parent[find(best[p].second)] = find(other);
      }
    }
  }
  std::map<size_t, size_t> index_of_root;
  for (size_t r = 0; r < parent.size(); ++r)
    index_of_root.try_emplace(find(r), index_of_root.size());
  segmentation.rooms.assign(index_of_root.size(), {});
  for (size_t p = 0; p < n; ++p) {
    if (best[p].second != kNone)
      segmentation.rooms[index_of_root.at(find(best[p].second))].push_back(places.ids[p]);
  }
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
