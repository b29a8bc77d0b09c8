#include "hydra_multi/backend/round_memory.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "hydra_multi/core/ascending_lookup.h"

namespace hydra_multi {
namespace {

using PoseLookup = AscendingLookup<std::map<NodeId, Eigen::Isometry3d>>;

bool sameTransform(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff() < 1e-9;
}

// Per node of `initial` that `poses` holds, the motion from one to the other: pose * initial^-1.
std::map<NodeId, Eigen::Isometry3d> correctionsOf(
    const std::map<NodeId, Eigen::Isometry3d>& poses,
    const std::map<NodeId, Eigen::Isometry3d>& initial) {
  std::map<NodeId, Eigen::Isometry3d> corrections;
  for (const auto& [id, pose] : poses) {
    const auto it = initial.find(id);
    if (it != initial.end())
      corrections.emplace_hint(corrections.end(), id, pose * it->second.inverse());
  }
  return corrections;
}

}  // namespace

void RoundMemory::remember(const SceneGraph& frontend, const DeformationGraph& graph,
                           const DeformationResult& result,
                           const std::map<NodeId, Eigen::Isometry3d>& proposal_poses,
                           const std::map<NodeId, Eigen::Isometry3d>& held_out_poses,
                           const std::map<RobotId, Eigen::Isometry3d>& T_global_robot, bool poses) {
  *this = RoundMemory();
  alignment_ = T_global_robot;
  if (!poses) return;
  whole_ = correctionsOf(result.poses, graph.initial);
  skeleton_ = correctionsOf(result.solve.poses, graph.initial);
  proposal_ = correctionsOf(proposal_poses, graph.skeleton.poses);
  held_out_ = correctionsOf(held_out_poses, graph.skeleton.poses);
  // Each robot's keyframes, latest first: a node new next round moves as the latest one did.
  std::map<RobotId, std::vector<std::pair<int64_t, NodeId>>> keyframes;
  for (const auto& [robot, T] : T_global_robot) {
    auto& stamped = keyframes[robot];
    for (const Node* node : frontend.robotNodes(robot)) {
      if (const AgentAttributes* agent = node->find<AgentAttributes>())
        stamped.emplace_back(agent->timestamp_ns, node->id);
    }
    std::sort(stamped.rbegin(), stamped.rend());
  }
  const auto latestOf = [&keyframes](const std::map<NodeId, Eigen::Isometry3d>& corrections) {
    std::map<RobotId, Eigen::Isometry3d> latest;
    for (const auto& [robot, stamped] : keyframes) {
      for (const auto& [stamp, id] : stamped) {
        if (const auto it = corrections.find(id); it != corrections.end()) {
          latest[robot] = it->second;
          break;
        }
      }
    }
    return latest;
  };
  latest_whole_ = latestOf(whole_);
  latest_proposal_ = latestOf(proposal_);
  latest_held_out_ = latestOf(held_out_);
  verdicts_ = result.robust_inlier;
  whole_owed_ = result.whole_graph_deferred;
}

std::set<RobotId> RoundMemory::alignedAsBefore(
    const std::map<RobotId, Eigen::Isometry3d>& T_global_robot) const {
  std::set<RobotId> kept;
  for (const auto& [robot, T] : T_global_robot) {
    const auto last = alignment_.find(robot);
    if (last != alignment_.end() && sameTransform(last->second, T)) kept.insert(robot);
  }
  return kept;
}

DeformationWarmStart RoundMemory::lastRound(
    const DeformationGraph& graph, const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    std::map<NodeId, Eigen::Isometry3d>* last_proposal,
    std::map<NodeId, Eigen::Isometry3d>* last_held_out) const {
  DeformationWarmStart warm;
  const std::set<RobotId> kept = alignedAsBefore(T_global_robot);
  const auto ofKept = [&kept](NodeId id) {
    const auto robot = id.sourceRobot();
    return robot && kept.count(*robot) != 0;
  };
  // A node's own correction, else (a node new since) that of its robot's latest keyframe.
  const auto moved = [](PoseLookup& own, const std::map<RobotId, Eigen::Isometry3d>& latest,
                        NodeId id,
                        const Eigen::Isometry3d& initial) -> std::optional<Eigen::Isometry3d> {
    if (const Eigen::Isometry3d* correction = own.find(id)) return *correction * initial;
    if (const auto it = latest.find(*id.sourceRobot()); it != latest.end())
      return it->second * initial;
    return std::nullopt;
  };
  // The nodes are visited in id order: each map grows at its end, each correction is walked once.
  PoseLookup whole(whole_), proposal(proposal_), held(held_out_);
  for (const auto& [id, initial] : graph.skeleton.poses) {
    if (!ofKept(id)) continue;
    if (const auto pose = moved(whole, latest_whole_, id, initial))
      warm.poses.emplace_hint(warm.poses.end(), id, *pose);
    if (last_proposal == nullptr) continue;
    if (const auto pose = moved(proposal, latest_proposal_, id, initial))
      last_proposal->emplace_hint(last_proposal->end(), id, *pose);
    if (const auto pose = moved(held, latest_held_out_, id, initial);
        pose && last_held_out != nullptr)
      last_held_out->emplace_hint(last_held_out->end(), id, *pose);
  }
  for (const auto& [edge, inlier] : verdicts_) {
    if (ofKept(edge.first) && ofKept(edge.second)) warm.verdicts[edge] = inlier;
  }
  // A graph assembled only as far as its skeleton (buildDeformationGraph) is solved no further:
  // its solve reads the earlier solutions of skeleton nodes alone.
  const std::map<NodeId, Eigen::Isometry3d>& nodes =
      graph.whole ? graph.initial : graph.skeleton.poses;
  PoseLookup whole_again(whole_), skeleton(skeleton_);
  for (const auto& [id, initial] : nodes) {
    if (!ofKept(id)) continue;
    if (const Eigen::Isometry3d* correction = whole_again.find(id))
      warm.last_whole.emplace_hint(warm.last_whole.end(), id, *correction * initial);
    if (const Eigen::Isometry3d* correction = skeleton.find(id))
      warm.last_skeleton.emplace_hint(warm.last_skeleton.end(), id, *correction * initial);
  }
  warm.whole_owed = whole_owed_;
  return warm;
}

}  // namespace hydra_multi
