#pragma once
// The merges of a round (paper III-B, NodeReconciliation): the merge candidates GNC kept are made
// in the backend graph, unless fewer than min_valid_share of those proposed were kept (then none
// is: the paper's undo); with label votes on, then the copies of one object that robots labelled
// differently (reconciliation.h). Each merge made is reported with what evaluation needs to check
// it (AcceptedMerge).

#include <map>
#include <memory>
#include <set>
#include <vector>

#include "hydra_multi/backend/reconciliation.h"
#include "hydra_multi/core/nearest_neighbors.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

/// A merge the backend made, with what evaluation needs to check it: each node as its robot
/// mapped it, its position and the robot's keyframe nearest to it among those of about the time
/// it last updated the node (stamp and pose), both in the robot's own frame (docs/DECISIONS.md:
/// "A merge is checked through the keyframe of its node's time").
struct AcceptedMerge {
  NodeId target, source;
  Layer layer = Layer::kPlaces;
  struct Side {
    RobotId robot;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    int64_t keyframe_stamp_ns = -1;  ///< -1: the robot has no keyframe
    Eigen::Isometry3d T_robot_keyframe = Eigen::Isometry3d::Identity();
  } target_side, source_side;
  /// Where the two copies were in the optimized map just before the merge (for display).
  Eigen::Vector3d target_optimized = Eigen::Vector3d::Zero();
  Eigen::Vector3d source_optimized = Eigen::Vector3d::Zero();
};

/// One robot's AcceptedMerge sides from the frontend graph (station ids, the robot's frame).
class MergeSideFinder {
 public:
  /// `mesh`: the robot's, for the time of an object (madeAtNs); `window_s`: how far from the
  /// node's time its keyframe may be (TimedNeighbors).
  MergeSideFinder(const SceneGraph& frontend, RobotId robot, const Mesh* mesh, double window_s);
  AcceptedMerge::Side side(NodeId id) const;

 private:
  const SceneGraph& frontend_;
  RobotId robot_;
  const Mesh* mesh_ = nullptr;
  std::vector<const Node*> keyframes_;
  std::unique_ptr<TimedNeighbors> near_;
};

struct MergeOutcome {
  std::vector<AcceptedMerge> merges;  ///< in the order made, label votes last
  size_t accepted = 0, undone = 0, label_merges = 0;
};

/// Makes in `graph` (the backend graph) the `candidates` whose factor GNC kept (`kept_factors`: per
/// factor (target, source)), or none if fewer than options.min_valid_share of them were kept; then,
/// with label votes, the label disputes. `meshes` and `window_s` are for the merge sides.
/// The same as placeMerged(graph, planMerges(graph, ...), the nodes' placements before).
MergeOutcome mergeKept(SceneGraph& graph, const SceneGraph& frontend,
                       const std::vector<MergeCandidate>& candidates,
                       const std::map<std::pair<NodeId, NodeId>, bool>& kept_factors,
                       const std::map<RobotId, const Mesh*>& meshes,
                       const ReconciliationOptions& options, double window_s);

/// mergeKept in two halves, so that the merges can be made before the graph is placed (while the
/// whole deformation graph is solved): planMerges makes them in `graph` as mergeKept does, but
/// for the nodes' positions and boxes, which it fuses from what the graph holds then; placeMerged
/// fuses them again from the nodes' placements (placeMap's) in the order made, writes the merged
/// nodes' and fills each merge's optimized positions, then makes the label disputes.
struct MergePlan {
  MergeOutcome outcome;  ///< the kept merges made, their optimized positions not yet filled
  bool made = false;     ///< enough were kept (min_valid_share): the label disputes follow
  std::map<NodeId, std::set<RobotId>> voters;  ///< per merged object, the robots its copies are of
};
/// Per candidate, whether GNC kept its factor (`kept_factors` as for mergeKept).
std::vector<bool> keptCandidates(const std::vector<MergeCandidate>& candidates,
                                 const std::map<std::pair<NodeId, NodeId>, bool>& kept_factors);
MergePlan planMerges(SceneGraph& graph, const SceneGraph& frontend,
                     const std::vector<MergeCandidate>& candidates, const std::vector<bool>& kept,
                     const std::map<RobotId, const Mesh*>& meshes, double window_s,
                     const ReconciliationOptions& options);
/// The nodes whose placement placeMerged needs: both ends of every merge in `plan`.
std::map<NodeId, Placement> mergedNodes(const MergePlan& plan);
/// `placed`: mergedNodes(plan) with each node's placement as placeMap gave it.
MergeOutcome placeMerged(SceneGraph& graph, MergePlan plan, std::map<NodeId, Placement> placed,
                         const SceneGraph& frontend, const std::map<RobotId, const Mesh*>& meshes,
                         const ReconciliationOptions& options, double window_s);

}  // namespace hydra_multi
