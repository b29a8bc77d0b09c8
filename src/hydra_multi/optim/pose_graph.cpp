#include "hydra_multi/optim/pose_graph.h"

#include <algorithm>
#include <deque>
#include <numeric>
#include <unordered_map>

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

void classifyEdges(PoseGraph& graph) {
  DisjointSets sets;
  bool in_prefix = true;
  for (PoseGraphEdge& edge : graph.edges) {
    in_prefix = in_prefix && sets.unite(edge.from, edge.to);
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

}  // namespace hydra_multi
