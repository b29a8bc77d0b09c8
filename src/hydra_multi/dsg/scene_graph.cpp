#include "hydra_multi/dsg/scene_graph.h"

#include <algorithm>
#include <stdexcept>

namespace hydra_multi {
namespace {

std::vector<uint64_t> unitedSorted(std::vector<uint64_t> a, const std::vector<uint64_t>& b) {
  a.insert(a.end(), b.begin(), b.end());
  std::sort(a.begin(), a.end());
  a.erase(std::unique(a.begin(), a.end()), a.end());
  return a;
}

// Fuses the attributes of `source` into `target` (same layer, not agents).
void fuseAttributes(Node& target, const Node& source) {
  std::optional<BoundingBox>& box = target.semantic()->bounding_box;
  const Placement fused =
      fusedPlacement({target.position, box}, {source.position, source.semantic()->bounding_box});
  target.position = fused.position;
  box = fused.box;
  target.last_update_time_ns = std::max(target.last_update_time_ns, source.last_update_time_ns);
  target.is_active = target.is_active || source.is_active;
  if (auto* object = target.find<ObjectAttributes>()) {
    object->mesh_vertices =
        unitedSorted(object->mesh_vertices, source.find<ObjectAttributes>()->mesh_vertices);
  }
  if (auto* place = target.find<PlaceAttributes>()) {
    const auto* other = source.find<PlaceAttributes>();
    place->distance = 0.5 * (place->distance + other->distance);
    place->mesh_vertices = unitedSorted(place->mesh_vertices, other->mesh_vertices);
  }
}

// A robot's nodes sorted by id: `node` added where it belongs (nearly always at the end of its
// category), or the node `id` taken out.
using RobotNodes = std::vector<std::pair<NodeId, Node*>>;
bool idBelow(const std::pair<NodeId, Node*>& entry, NodeId id) { return entry.first < id; }
void insertSorted(RobotNodes& nodes, Node* node) {
  if (nodes.empty() || nodes.back().first < node->id) {
    nodes.emplace_back(node->id, node);
  } else {
    nodes.insert(std::lower_bound(nodes.begin(), nodes.end(), node->id, idBelow), {node->id, node});
  }
}
void eraseSorted(RobotNodes& nodes, NodeId id) {
  const auto it = std::lower_bound(nodes.begin(), nodes.end(), id, idBelow);
  if (it != nodes.end() && it->first == id) nodes.erase(it);
}

}  // namespace

Placement fusedPlacement(const Placement& target, const Placement& source) {
  Placement fused{0.5 * (target.position + source.position), target.box};
  if (target.box && source.box) {
    fused.box = target.box->merged(*source.box);
  } else if (!target.box) {
    fused.box = source.box;
  }
  return fused;
}

SceneGraph::SceneGraph(const SceneGraph& other)
    : nodes_(other.nodes_),
      edges_(other.edges_),
      adjacency_(other.adjacency_),
      by_robot_(other.by_robot_),
      by_robot_layer_(other.by_robot_layer_),
      by_layer_(other.by_layer_),
      mesh_(other.mesh_) {
  index_.reserve(nodes_.size());
  for (auto& [id, node] : nodes_) index_.emplace(id, &node);
  for (auto& [robot, nodes] : by_robot_) {
    for (auto& [id, node] : nodes) node = index_.at(id);  // this graph's own
  }
}

SceneGraph& SceneGraph::operator=(const SceneGraph& other) {
  if (this != &other) *this = SceneGraph(other);
  return *this;
}

bool SceneGraph::addOrUpdateNode(Node node) {
  const auto known = index_.find(node.id);
  if (known == index_.end()) {
    const NodeId id = node.id;
    Node& added = nodes_.emplace(id, std::move(node)).first->second;
    if (const auto robot = added.robot()) {
      insertSorted(by_robot_[*robot], &added);
      by_robot_layer_[{*robot, added.layer()}].insert(id);
    }
    by_layer_[added.layer()].insert(id);
    index_.emplace(id, &added);
    adjacency_[id];
    return true;
  }
  Node& existing = *known->second;
  if (existing.layer() != node.layer()) {
    throw std::invalid_argument("node " + node.id.str() + " exists in layer " +
                                layerName(existing.layer()) + ", not " + layerName(node.layer()));
  }
  existing = std::move(node);
  return false;
}

bool SceneGraph::removeNode(NodeId id) {
  auto it = nodes_.find(id);
  if (it == nodes_.end()) return false;
  index_.erase(id);
  const auto adjacent = adjacency_.find(id);
  for (const NodeId other : adjacent->second) {
    edges_.erase(EdgeKey(id, other));
    adjacency_.at(other).erase(id);
  }
  adjacency_.erase(adjacent);
  if (const auto robot = it->second.robot()) {
    const auto of_robot = by_robot_.find(*robot);
    eraseSorted(of_robot->second, id);
    if (of_robot->second.empty()) by_robot_.erase(of_robot);
    const auto of_layer = by_robot_layer_.find({*robot, it->second.layer()});
    of_layer->second.erase(id);
    if (of_layer->second.empty()) by_robot_layer_.erase(of_layer);
  }
  by_layer_[it->second.layer()].erase(id);
  nodes_.erase(it);
  return true;
}

const Node* SceneGraph::findNode(NodeId id) const {
  const auto it = index_.find(id);
  return it == index_.end() ? nullptr : it->second;
}

const Node& SceneGraph::getNode(NodeId id) const {
  const Node* node = findNode(id);
  if (!node) throw std::out_of_range("no node " + id.str());
  return *node;
}

Node* SceneGraph::findMutableNode(NodeId id) {
  const auto it = index_.find(id);
  return it == index_.end() ? nullptr : it->second;
}

bool SceneGraph::addOrUpdateEdge(NodeId a, NodeId b, EdgeAttributes info) {
  const Node* node_a = findNode(a);
  const Node* node_b = findNode(b);
  if (!node_a || !node_b) {
    throw std::invalid_argument("edge " + a.str() + " - " + b.str() + ": endpoint " +
                                (node_a ? b : a).str() + " does not exist");
  }
  if (a == b) throw std::invalid_argument("edge " + a.str() + " - " + b.str() + ": self-loop");
  if (!isValidEdge(node_a->layer(), node_b->layer())) {
    throw std::invalid_argument("edge " + a.str() + " - " + b.str() + ": layers " +
                                layerName(node_a->layer()) + " and " + layerName(node_b->layer()) +
                                " may not be joined");
  }
  const EdgeKey key(a, b);
  auto it = edges_.find(key);
  if (it != edges_.end()) {
    it->second = info;
    return false;
  }
  // One parent per node: a new parent edge replaces the child's old one.
  const int level_a = layerLevel(node_a->layer());
  const int level_b = layerLevel(node_b->layer());
  if (level_a != level_b) {
    const NodeId child = level_a < level_b ? a : b;
    if (const auto old_parent = parent(child)) removeEdge(child, *old_parent);
  }
  edges_.emplace(key, info);
  adjacency_[a].insert(b);
  adjacency_[b].insert(a);
  return true;
}

bool SceneGraph::removeEdge(NodeId a, NodeId b) {
  if (edges_.erase(EdgeKey(a, b)) == 0) return false;
  adjacency_[a].erase(b);
  adjacency_[b].erase(a);
  return true;
}

const EdgeAttributes* SceneGraph::findEdge(NodeId a, NodeId b) const {
  auto it = edges_.find(EdgeKey(a, b));
  return it == edges_.end() ? nullptr : &it->second;
}

std::vector<NodeId> SceneGraph::neighbours(NodeId id) const {
  std::vector<NodeId> result;
  const Node* node = findNode(id);
  if (!node) return result;
  for (const NodeId other : adjacency_.at(id)) {
    if (getNode(other).layer() == node->layer()) result.push_back(other);
  }
  return result;
}

std::vector<NodeId> SceneGraph::adjacent(NodeId id) const {
  auto it = adjacency_.find(id);
  if (it == adjacency_.end()) return {};
  return {it->second.begin(), it->second.end()};
}

std::optional<NodeId> SceneGraph::parent(NodeId id) const {
  const Node* node = findNode(id);
  if (!node) return std::nullopt;
  for (const NodeId other : adjacency_.at(id)) {
    if (layerLevel(getNode(other).layer()) > layerLevel(node->layer())) return other;
  }
  return std::nullopt;
}

std::vector<NodeId> SceneGraph::children(NodeId id) const {
  std::vector<NodeId> result;
  const Node* node = findNode(id);
  if (!node) return result;
  for (const NodeId other : adjacency_.at(id)) {
    if (layerLevel(getNode(other).layer()) < layerLevel(node->layer())) result.push_back(other);
  }
  return result;
}

std::vector<NodeId> SceneGraph::nodesInLayer(Layer layer) const {
  const auto it = by_layer_.find(layer);
  if (it == by_layer_.end()) return {};
  return {it->second.begin(), it->second.end()};
}

std::vector<NodeId> SceneGraph::nodesOfRobot(RobotId robot) const {
  std::vector<NodeId> ids;
  if (const auto it = by_robot_.find(robot); it != by_robot_.end()) {
    ids.reserve(it->second.size());
    for (const auto& [id, node] : it->second) ids.push_back(id);
  }
  return ids;
}

std::vector<const Node*> SceneGraph::robotNodes(RobotId robot) const {
  std::vector<const Node*> nodes;
  if (const auto it = by_robot_.find(robot); it != by_robot_.end()) {
    nodes.reserve(it->second.size());
    for (const auto& [id, node] : it->second) nodes.push_back(node);
  }
  return nodes;
}

std::vector<NodeId> SceneGraph::nodesOfRobot(RobotId robot, Layer layer) const {
  const auto it = by_robot_layer_.find({robot, layer});
  if (it == by_robot_layer_.end()) return {};
  return {it->second.begin(), it->second.end()};
}

std::vector<RobotId> SceneGraph::robots() const {
  std::set<RobotId> robots;
  for (const auto& [robot, ids] : by_robot_) robots.insert(robot);
  for (const MeshVertex& vertex : mesh_.vertices) robots.insert(vertex.robot);
  return {robots.begin(), robots.end()};
}

size_t SceneGraph::numNodes(Layer layer) const {
  const auto it = by_layer_.find(layer);
  return it == by_layer_.end() ? 0 : it->second.size();
}

size_t SceneGraph::numNodes(RobotId robot, Layer layer) const {
  const auto it = by_robot_layer_.find({robot, layer});
  return it == by_robot_layer_.end() ? 0 : it->second.size();
}

void SceneGraph::mergeNodes(NodeId target, NodeId source, MergeRecord* record) {
  const Node* target_node = findNode(target);
  const Node* source_node = findNode(source);
  if (!target_node || !source_node || target == source) {
    throw std::invalid_argument("merge " + source.str() + " into " + target.str() +
                                ": both nodes must exist and differ");
  }
  if (target_node->layer() != source_node->layer() || target_node->layer() == Layer::kAgents) {
    throw std::invalid_argument("merge " + source.str() + " into " + target.str() +
                                ": only nodes of one layer other than agents merge");
  }
  if (record != nullptr) {
    record->target_before = *target_node;
    record->source = *source_node;
  }
  std::vector<Edge> source_edges;
  for (const NodeId other : adjacency_.at(source))
    source_edges.push_back({source, other, edges_.at(EdgeKey(source, other))});
  // The source's edges the target takes: not to itself, not one it has, not a second parent.
  const int target_level = layerLevel(target_node->layer());
  const bool target_has_parent = parent(target).has_value();
  std::vector<const Edge*> moved;
  for (const Edge& edge : source_edges) {
    const NodeId other = edge.target;
    if (other == target || hasEdge(target, other)) continue;
    const bool is_parent_edge = layerLevel(getNode(other).layer()) > target_level;
    if (is_parent_edge && target_has_parent) continue;
    moved.push_back(&edge);
  }
  fuseAttributes(*findMutableNode(target), *source_node);
  removeNode(source);
  for (const Edge* edge : moved) addOrUpdateEdge(target, edge->target, edge->info);
  if (record == nullptr) return;
  for (const Edge* edge : moved) record->moved_to_target.push_back(edge->target);
  record->source_edges = std::move(source_edges);
}

Status SceneGraph::undoMerge(const MergeRecord& record) {
  const NodeId target = record.target_before.id;
  if (!hasNode(target)) return Error{"undo merge: target " + target.str() + " no longer exists"};
  if (hasNode(record.source.id)) {
    return Error{"undo merge: source id " + record.source.id.str() + " is in use again"};
  }
  for (const NodeId other : record.moved_to_target) removeEdge(target, other);
  addOrUpdateNode(record.target_before);
  addOrUpdateNode(record.source);
  for (const Edge& edge : record.source_edges) {
    if (hasNode(edge.target)) addOrUpdateEdge(edge.source, edge.target, edge.info);
  }
  return Status::Ok();
}

bool SceneGraph::operator==(const SceneGraph& other) const {
  return nodes_ == other.nodes_ && edges_ == other.edges_ && mesh_ == other.mesh_;
}

}  // namespace hydra_multi
