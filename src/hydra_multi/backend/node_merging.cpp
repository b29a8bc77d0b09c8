#include "hydra_multi/backend/node_merging.h"

#include <set>

#include "hydra_multi/backend/deformation_graph.h"

namespace hydra_multi {

MergeSideFinder::MergeSideFinder(const SceneGraph& frontend, RobotId robot, const Mesh* mesh,
                                 double window_s)
    : frontend_(frontend), robot_(robot), mesh_(mesh) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<int64_t> times;
  for (const NodeId id : frontend.nodesOfRobot(robot)) {
    const Node& node = frontend.getNode(id);
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

MergeOutcome mergeKept(SceneGraph& graph, const SceneGraph& frontend,
                       const std::vector<MergeCandidate>& candidates,
                       const std::map<std::pair<NodeId, NodeId>, bool>& kept_factors,
                       const std::map<RobotId, const Mesh*>& meshes,
                       const ReconciliationOptions& options, double window_s) {
  MergeOutcome outcome;
  std::vector<const MergeCandidate*> kept;
  for (const MergeCandidate& c : candidates) {
    const auto it = kept_factors.find({c.target, c.source});
    if (it != kept_factors.end() && it->second) kept.push_back(&c);
  }
  if (!candidates.empty() &&
      double(kept.size()) >= options.min_valid_share * double(candidates.size())) {
    std::map<RobotId, MergeSideFinder> sides;
    const auto side = [&](NodeId id) {
      const RobotId robot = id.sourceRobot().value_or(RobotId(0));
      const auto mesh = meshes.find(robot);
      const auto it = sides
                          .try_emplace(robot, frontend, robot,
                                       mesh == meshes.end() ? nullptr : mesh->second, window_s)
                          .first;
      return it->second.side(id);
    };
    // The robots whose copies each merged object unites, for the label votes.
    std::map<NodeId, std::set<RobotId>> voters;
    for (const MergeCandidate* c : kept) {
      if (!graph.hasNode(c->target) || !graph.hasNode(c->source)) continue;
      outcome.merges.push_back({c->target, c->source, c->layer, side(c->target), side(c->source),
                                graph.getNode(c->target).position,
                                graph.getNode(c->source).position});
      graph.mergeNodes(c->target, c->source);
      ++outcome.accepted;
      if (c->layer != Layer::kObjects) continue;
      for (const NodeId id : {c->target, c->source}) {
        if (const auto robot = id.sourceRobot()) voters[c->target].insert(*robot);
      }
    }
    if (options.label_votes) {
      for (const LabelDispute& d : resolveLabelDisputes(graph, voters, options)) {
        outcome.merges.push_back({d.winner, d.loser, Layer::kObjects, side(d.winner), side(d.loser),
                                  graph.getNode(d.winner).position,
                                  graph.getNode(d.loser).position});
        graph.mergeNodes(d.winner, d.loser);
        ++outcome.label_merges;
      }
    }
  } else {
    outcome.undone = kept.size();
  }

  return outcome;
}

}  // namespace hydra_multi
