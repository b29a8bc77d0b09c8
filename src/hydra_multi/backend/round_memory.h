#pragma once
// What an incremental backend round keeps for the next (BackendOptions::incremental) and the
// warm starts made from it. Per node of the deformation graph it keeps the motion
// C = optimized * initial^-1 (global frame) of each of the round's solves: the whole graph's, the
// skeleton with merges', and the loop closures' solve's with and without what it re-admitted; per
// robot, those of its latest keyframe; the robots' alignment; the robust factors' verdicts. A node
// of the next round starts at C * initial with its own C, or (new since) its robot's latest
// keyframe's. Only nodes and factors of robots aligned as before take anything.
// docs/DECISIONS.md: "Rounds start where the last one ended".

#include <map>
#include <set>
#include <utility>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

class RoundMemory {
 public:
  /// Forgets the last round, then keeps this one's alignment and, with `poses`, its solutions
  /// and verdicts. `proposal_poses`, `held_out_poses`: the loop closures' solve with and
  /// without what it re-admitted (skeleton nodes).
  void remember(const SceneGraph& frontend, const DeformationGraph& graph,
                const DeformationResult& result,
                const std::map<NodeId, Eigen::Isometry3d>& proposal_poses,
                const std::map<NodeId, Eigen::Isometry3d>& held_out_poses,
                const std::map<RobotId, Eigen::Isometry3d>& T_global_robot, bool poses);

  /// The robots of `T_global_robot` aligned as in the last round.
  std::set<RobotId> alignedAsBefore(
      const std::map<RobotId, Eigen::Isometry3d>& T_global_robot) const;

  /// Where the last round left the robots aligned as they were: its verdicts on robust factors,
  /// the poses of `graph`'s skeleton, those of its last two solves
  /// (DeformationWarmStart::last_whole, last_skeleton) and, into `last_proposal`, those of its
  /// loop closures' solve (into `last_held_out`, that solve's before its re-admission).
  DeformationWarmStart lastRound(
      const DeformationGraph& graph, const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
      std::map<NodeId, Eigen::Isometry3d>* last_proposal = nullptr,
      std::map<NodeId, Eigen::Isometry3d>* last_held_out = nullptr) const;

 private:
  std::map<NodeId, Eigen::Isometry3d> whole_, skeleton_, proposal_, held_out_;
  std::map<RobotId, Eigen::Isometry3d> latest_whole_, latest_proposal_, latest_held_out_;
  std::map<RobotId, Eigen::Isometry3d> alignment_;
  std::map<std::pair<NodeId, NodeId>, bool> verdicts_;
  bool whole_owed_ = false;  ///< the last round deferred its whole-graph solve
};

}  // namespace hydra_multi
