#pragma once
// Reconciliation proposals (paper III-B): nodes of different aligned robots that look like one.
//   places   centres within place_max_distance and radii within place_max_radius_difference
//            (Hydra's single-robot thresholds 0.4 m and 0.3 m; the paper's 0.01 m suits robots
//            that share a places reconstruction, which ours do not); each place in one pair at
//            most, nearest first;
//   objects  the same label and overlapping bounding boxes (either box holds the other's
//            centre; Hydra's test), nearest first.
// Each candidate becomes a robust factor of the deformation graph (deformation_graph.h) that says
// the two nodes are at one position (their rotations as aligned). After the solve,
// NodeReconciliation merges the candidates GNC kept, unless fewer than min_valid_share of the
// proposed ones were kept: then none of this round's merges is made (the paper's undo). The backend
// graph is rebuilt every round, so a merge is taken back whenever a later round no longer supports
// it.

#include <map>
#include <vector>

#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct ReconciliationOptions {
  double place_max_distance = 0.4;
  double place_max_radius_difference = 0.3;
  double min_valid_share = 0.5;
  double merge_variance = 5e-2;  ///< of the merge factors (as loop closures)
};

struct MergeCandidate {
  NodeId target, source;  ///< the source merges into the target
  Layer layer = Layer::kPlaces;
};

/// Candidates among the places and objects of the aligned robots (`T_global_robot`) of
/// `frontend` (each robot's nodes in its own frame).
std::vector<MergeCandidate> proposeMerges(
    const SceneGraph& frontend, const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const ReconciliationOptions& options = {});

/// The merge factors: between-factors of zero translation, with the rotation the alignment gives.
std::vector<PoseGraphEdge> mergeFactors(const std::vector<MergeCandidate>& candidates,
                                        const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
                                        const ReconciliationOptions& options = {});

}  // namespace hydra_multi
