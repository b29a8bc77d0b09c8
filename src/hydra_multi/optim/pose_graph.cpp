#include "hydra_multi/optim/pose_graph.h"

#include <algorithm>
#include <deque>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace hydra_multi {
namespace {

// Union-find over node ids, for detecting the first edge that closes a cycle.
class DisjointSets {
 public:
  NodeId find(NodeId x) {
    auto it = parent_.find(x);
    if (it == parent_.end()) return parent_[x] = x;
    if (it->second == x) return x;
    return it->second = find(it->second);
  }
  bool unite(NodeId a, NodeId b) {
    const NodeId ra = find(a), rb = find(b);
    if (ra == rb) return false;
    parent_[ra] = rb;
    return true;
  }

 private:
  std::unordered_map<NodeId, NodeId> parent_;
};

bool consecutive(NodeId a, NodeId b) {
  return a.category() == b.category() && a.isStation() == b.isStation() &&
         (a.index() + 1 == b.index() || b.index() + 1 == a.index());
}

}  // namespace

size_t PoseGraph::numLoopClosures() const {
  return static_cast<size_t>(std::count_if(edges.begin(), edges.end(), [](const PoseGraphEdge& e) {
    return e.kind == PoseGraphEdge::Kind::kLoopClosure;
  }));
}

void classifyEdges(PoseGraph& graph, size_t max_odometry_components) {
  // Components of the graph under consecutive-id edges alone.
  DisjointSets odometry;
  std::unordered_set<NodeId> nodes;
  for (const auto& [id, T] : graph.poses) nodes.insert(id);
  for (const PoseGraphEdge& edge : graph.edges) {
    nodes.insert(edge.from);
    nodes.insert(edge.to);
    if (consecutive(edge.from, edge.to)) odometry.unite(edge.from, edge.to);
  }
  std::unordered_set<NodeId> roots;
  for (const NodeId id : nodes) roots.insert(odometry.find(id));
  const bool use_prefix = roots.size() > max_odometry_components;

  DisjointSets prefix;
  bool in_prefix = use_prefix;
  for (PoseGraphEdge& edge : graph.edges) {
    in_prefix = in_prefix && prefix.unite(edge.from, edge.to);
    edge.kind = (in_prefix || consecutive(edge.from, edge.to)) ? PoseGraphEdge::Kind::kOdometry
                                                               : PoseGraphEdge::Kind::kLoopClosure;
  }
}

std::map<NodeId, Eigen::Isometry3d> odometryInitialization(const PoseGraph& graph, NodeId root) {
  std::unordered_map<NodeId, std::vector<const PoseGraphEdge*>> adjacency;
  for (const PoseGraphEdge& edge : graph.edges) {
    if (edge.kind != PoseGraphEdge::Kind::kOdometry) continue;
    adjacency[edge.from].push_back(&edge);
    adjacency[edge.to].push_back(&edge);
  }
  std::map<NodeId, Eigen::Isometry3d> poses;
  poses[root] = Eigen::Isometry3d::Identity();
  std::deque<NodeId> queue = {root};
  while (!queue.empty()) {
    const NodeId current = queue.front();
    queue.pop_front();
    const Eigen::Isometry3d T_world_current = poses.at(current);
    for (const PoseGraphEdge* edge : adjacency[current]) {
      const bool forward = edge->from == current;
      const NodeId next = forward ? edge->to : edge->from;
      if (poses.count(next)) continue;
      poses[next] = T_world_current * (forward ? edge->T_from_to : edge->T_from_to.inverse());
      queue.push_back(next);
    }
  }
  return poses;
}

std::map<NodeId, Eigen::Isometry3d> spanningInitialization(const PoseGraph& graph, NodeId root) {
  std::unordered_map<NodeId, std::vector<const PoseGraphEdge*>> adjacency;
  for (const PoseGraphEdge& edge : graph.edges) {
    adjacency[edge.from].push_back(&edge);
    adjacency[edge.to].push_back(&edge);
  }
  std::unordered_map<NodeId, int> distance = {{root, 0}};
  std::map<NodeId, Eigen::Isometry3d> poses = {{root, Eigen::Isometry3d::Identity()}};
  std::deque<NodeId> queue = {root};
  while (!queue.empty()) {
    const NodeId current = queue.front();
    queue.pop_front();
    for (const PoseGraphEdge* edge : adjacency[current]) {
      const int cost = edge->kind == PoseGraphEdge::Kind::kOdometry ? 0 : 1;
      const bool forward = edge->from == current;
      const NodeId next = forward ? edge->to : edge->from;
      const int d = distance.at(current) + cost;
      if (auto it = distance.find(next); it != distance.end() && it->second <= d) continue;
      distance[next] = d;
      poses[next] = poses.at(current) * (forward ? edge->T_from_to : edge->T_from_to.inverse());
      if (cost == 0) {
        queue.push_front(next);
      } else {
        queue.push_back(next);
      }
    }
  }
  return poses;
}

}  // namespace hydra_multi
