#include "hydra_multi/backend/node_merging.h"

#include <algorithm>
#include <set>

#include "hydra_multi/backend/deformation_graph.h"

namespace hydra_multi {

MergeSideFinder::MergeSideFinder(const SceneGraph& frontend, RobotId robot, const Mesh* mesh,
                                 double window_s)
    : frontend_(frontend), robot_(robot), mesh_(mesh) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int64_t> times;
  for (const Node* robot_node : frontend.robotNodes(robot)) {
    const Node& node = *robot_node;
    if (node.layer() != Layer::kAgents || node.find<AgentAttributes>() == nullptr) continue;
    keyframes_.push_back(&node);
    positions.push_back(node.position);
    times.push_back(node.find<AgentAttributes>()->timestamp_ns);
  }
  near_ = std::make_unique<TimedNeighbors>(positions, times, windowNs(window_s));
}

AcceptedMerge::Side MergeSideFinder::side(NodeId id) const {
  AcceptedMerge::Side s;
  s.robot = robot_;
  const Node* node = frontend_.findNode(id);
  if (node == nullptr) return s;
  s.position = node->position;
  const auto nearest = near_->nearest(s.position, madeAtNs(*node, mesh_));
  if (nearest.empty()) return s;
  const Node& keyframe = *keyframes_[nearest.front().index];
  s.keyframe_stamp_ns = keyframe.find<AgentAttributes>()->timestamp_ns;
  s.T_robot_keyframe = nodePose(keyframe);
  return s;
}

namespace {

// The sides of merges, each robot's MergeSideFinder made when first asked.
class MergeSides {
 public:
  MergeSides(const SceneGraph& frontend, const std::map<RobotId, const Mesh*>& meshes,
             double window_s)
      : frontend_(frontend), meshes_(meshes), window_s_(window_s) {}
  AcceptedMerge::Side operator()(NodeId id) {
    const RobotId robot = id.sourceRobot().value_or(RobotId(0));
    const auto mesh = meshes_.find(robot);
    const auto it = finders_
                        .try_emplace(robot, frontend_, robot,
                                     mesh == meshes_.end() ? nullptr : mesh->second, window_s_)
                        .first;
    return it->second.side(id);
  }

 private:
  const SceneGraph& frontend_;
  const std::map<RobotId, const Mesh*>& meshes_;
  double window_s_;
  std::map<RobotId, MergeSideFinder> finders_;
};

}  // namespace

std::vector<bool> keptCandidates(const std::vector<MergeCandidate>& candidates,
                                 const std::map<std::pair<NodeId, NodeId>, bool>& kept_factors) {
  std::vector<bool> kept(candidates.size(), false);
  for (size_t i = 0; i < candidates.size(); ++i) {
    const auto it = kept_factors.find({candidates[i].target, candidates[i].source});
    kept[i] = it != kept_factors.end() && it->second;
  }
  return kept;
}

MergePlan planMerges(SceneGraph& graph, const SceneGraph& frontend,
                     const std::vector<MergeCandidate>& candidates, const std::vector<bool>& kept,
                     const std::map<RobotId, const Mesh*>& meshes, double window_s,
                     const ReconciliationOptions& options) {
  MergePlan plan;
  const size_t n_kept = size_t(std::count(kept.begin(), kept.end(), true));
  if (candidates.empty() || double(n_kept) < options.min_valid_share * double(candidates.size())) {
    plan.outcome.undone = n_kept;
    return plan;
  }
  plan.made = true;
  plan.outcome.merges.reserve(n_kept);
  MergeSides side(frontend, meshes, window_s);
  for (size_t i = 0; i < candidates.size(); ++i) {
    const MergeCandidate& c = candidates[i];
    if (!kept[i] || !graph.hasNode(c.target) || !graph.hasNode(c.source)) continue;
    plan.outcome.merges.push_back({c.target, c.source, c.layer, side(c.target), side(c.source)});
    graph.mergeNodes(c.target, c.source);
    ++plan.outcome.accepted;
    if (c.layer != Layer::kObjects) continue;
    for (const NodeId id : {c.target, c.source}) {
      if (const auto robot = id.sourceRobot()) plan.voters[c.target].insert(*robot);
    }
  }
  return plan;
}

std::map<NodeId, Placement> mergedNodes(const MergePlan& plan) {
  std::map<NodeId, Placement> nodes;
  for (const AcceptedMerge& m : plan.outcome.merges) {
    nodes[m.target];
    nodes[m.source];
  }
  return nodes;
}

MergeOutcome placeMerged(SceneGraph& graph, MergePlan plan, std::map<NodeId, Placement> placed,
                         const SceneGraph& frontend, const std::map<RobotId, const Mesh*>& meshes,
                         const ReconciliationOptions& options, double window_s) {
  MergeOutcome& outcome = plan.outcome;
  for (AcceptedMerge& m : outcome.merges) {
    Placement& target = placed.at(m.target);
    const Placement& source = placed.at(m.source);
    m.target_optimized = target.position;
    m.source_optimized = source.position;
    target = fusedPlacement(target, source);
  }
  for (const AcceptedMerge& m : outcome.merges) {
    Node* node = graph.findMutableNode(m.target);  // none: merged on into another
    if (node == nullptr) continue;
    const Placement& fused = placed.at(m.target);
    node->position = fused.position;
    node->semantic()->bounding_box = fused.box;
  }
  if (options.label_votes && plan.made) {
    MergeSides side(frontend, meshes, window_s);
    for (const LabelDispute& d : resolveLabelDisputes(graph, plan.voters, options)) {
      outcome.merges.push_back({d.winner, d.loser, Layer::kObjects, side(d.winner), side(d.loser),
                                graph.getNode(d.winner).position, graph.getNode(d.loser).position});
      graph.mergeNodes(d.winner, d.loser);
      ++outcome.label_merges;
    }
  }
  return std::move(plan.outcome);
}

MergeOutcome mergeKept(SceneGraph& graph, const SceneGraph& frontend,
                       const std::vector<MergeCandidate>& candidates,
                       const std::map<std::pair<NodeId, NodeId>, bool>& kept_factors,
                       const std::map<RobotId, const Mesh*>& meshes,
                       const ReconciliationOptions& options, double window_s) {
  const std::vector<bool> kept = keptCandidates(candidates, kept_factors);
  std::map<NodeId, Placement> placed;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (!kept[i]) continue;
    for (const NodeId id : {candidates[i].target, candidates[i].source}) {
      if (const Node* node = graph.findNode(id))
        placed[id] = {node->position, node->semantic()->bounding_box};
    }
  }
  MergePlan plan = planMerges(graph, frontend, candidates, kept, meshes, window_s, options);
  return placeMerged(graph, std::move(plan), std::move(placed), frontend, meshes, options,
                     window_s);
}

}  // namespace hydra_multi
