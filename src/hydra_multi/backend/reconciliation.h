#pragma once
// Reconciliation proposals (paper III-B): nodes of different aligned robots that look like one.
//   places   centres within place_max_distance and radii within place_max_radius_difference
//            (0.3 m and 0.3 m; the paper's 0.01 m suits robots that share a places
//            reconstruction, which ours do not). 0.3 m was chosen over Hydra's single-robot 0.4 m
//            when the team's map was ~1 m off on dorm-2 seed 3 and 0.4 m merged places 1.1-1.3 m
//            apart in truth at doorways (as the merge check measured then: it placed nodes through
//            keyframes of other passes, backend.h MergeSideFinder); since the map and the check are
//            right, 0.4 m makes 2-4 more merges, none across rooms, and the same metrics (dorm-2
//            seed 3, office-3 seed 1);
//   objects  the same label and overlapping bounding boxes (either box holds the other's
//            centre; Hydra's test).
// Matching nodes are grouped, nearest pairs first, at most one node of each robot in a group (three
// robots' copies of one object make one group; as pairs, each node in one pair at most, the third
// copy was left over on every round); every other node of a group merges into the group's node of
// the lowest robot index.
// Object candidates are then checked by ICP of the source object's mesh vertices onto the
// target's (refineObjectMerges, registration/icp.h): a pair whose surfaces do not fit (too few
// vertices paired, too large an error, the copy moved too far) is dropped; a fit that turns the
// copy too far is taken for a wrong fit of two partial surfaces, and the pair keeps the plain
// factor (dropping such pairs left 16 duplicates of 260 objects on office-3 seed 1 with
// ground-truth labels, monitors and chairs turned 21-178 degrees; with the plain factor 5); for
// the others ICP's transform gives the merge factor's measurement. Each candidate becomes a robust
// factor of the deformation graph (deformation_graph.h): the relative pose ICP found, or for places
// (and objects without vertices or ICP's measurement) the two nodes at one position. The backend
// proposes on the map its loop closures optimized and holds the factors out of GNC, keeping those
// that fit its result (backend.h). NodeReconciliation then merges the kept candidates, unless fewer
// than min_valid_share of the proposed ones were kept: then none of this round's merges is made
// (the paper's undo). The backend graph is rebuilt every round, so a merge is taken back whenever a
// later round no longer supports it.
//
// Label votes (beyond the paper; off by default, `reconciliation.label_votes`): the paper merges
// objects of one label only, so where two robots label one object differently (a detector's
// confusion: chair and sofa, monitor and printer) the team's graph keeps both, one of them wrong.
// resolveLabelDisputes finds such pairs in the backend graph after the merges: objects of
// different robots and labels whose boxes overlap (as above) and whose deformed mesh vertices
// coincide (most of the smaller object's vertices within label_vertex_distance_m of the other's:
// one surface, not a chair under a table). The label follows Bayes with a confusion of
// label_confusion per robot, the same between any two labels: the odds of label A over B are
//   (n_A + 1) / (n_B + 1) * ((1 - p) / p)^(k_A - k_B),
// n the objects of that label in the team's graph (the prior), k the robots that gave it. A pair
// whose odds reach label_min_odds either way merges into the winner; others stay as they are.
// Measured with the simulator's 10 % confusion, drawn per robot and object (full system, 5 seeds
// each, `config/label-votes.json`; README): wrong-label objects 38.0 -> 12.6 per run on office-3,
// 17.6 -> 11.0 on the dorm floors, 11.4 -> 10.0 on residence-3f; objects correct 86.3 -> 95.0 %,
// 91.9 -> 94.7 %, 93.9 -> 94.6 %. The prior speaks against a true object of the rarer label, and
// where its one right copy loses the vote it is no longer found: objects found 93.7 -> 93.3 % on
// office-3, 90.1 -> 89.7 % on the dorm floors, the same on residence-3f. Hence off by default:
// the paper's rule keeps every object found that a robot labelled right.

#include <map>
#include <optional>
#include <set>
#include <vector>

#include "hydra_multi/dsg/mesh.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct ReconciliationOptions {
  double place_max_distance = 0.3;
  double place_max_radius_difference = 0.3;
  double min_valid_share = 0.5;
  double merge_variance = 5e-2;  ///< of the merge factors (as loop closures)
  /// Rotation variance of merge factors without an ICP measurement (places): so loose the factor
  /// holds positions only. With merge_variance there, drift-corrected rotations of two robots'
  /// places failed it (office-3 seed 4: fewer than half kept, every merge undone).
  double unmeasured_rotation_variance = 1e4;
  /// ICP of object candidates: kept when at least this share of the source's vertices pair
  /// with the target's within the correspondence distance, with at most this error, moving the
  /// source's vertex centroid at most icp_max_shift_m and turning it at most
  /// icp_max_rotation_deg (the robots are aligned: a larger turn is a symmetric shape fitted
  /// the wrong way round, office-3 seed 1: 14 of 282 fits between 20 and 175 degrees; such a
  /// pair keeps the plain factor).
  bool object_icp = true;
  double icp_min_paired_share = 0.5;
  double icp_max_rmse_m = 0.2;
  double icp_max_shift_m = 1.0;
  double icp_max_rotation_deg = 20.0;
  size_t icp_min_vertices = 8;  ///< fewer on either side: no ICP, the plain factor
  /// Label votes (see the top of this file); objects with fewer than icp_min_vertices vertices
  /// take no part.
  bool label_votes = false;
  double label_confusion = 0.1;  ///< the chance a robot's label is wrong, as the vote assumes
  double label_min_odds = 3.0;
  double label_vertex_distance_m = 0.1;
  double label_min_shared_vertices = 0.5;  ///< share of the smaller object's vertices
};

struct MergeCandidate {
  NodeId target, source;  ///< the source merges into the target
  Layer layer = Layer::kPlaces;
  /// From ICP: the factor's measurement T_target_source (node poses as the deformation graph
  /// initializes them); absent: the plain one.
  std::optional<Eigen::Isometry3d> T_target_source;
};

/// Candidates among the places and objects of the aligned robots (`T_global_robot`) of
/// `frontend` (each robot's nodes in its own frame). `optimized`, when given, holds global
/// positions of nodes from the previous round's optimization, used instead of the aligned ones:
/// the merge factors are tested against the optimized graph, where drift no longer separates the
/// robots' copies of a place.
std::vector<MergeCandidate> proposeMerges(
    const SceneGraph& frontend, const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const ReconciliationOptions& options = {},
    const std::map<NodeId, Eigen::Vector3d>* optimized = nullptr);

/// Checks the object candidates by ICP on their mesh vertices (`meshes`: each robot's, in its own
/// frame); drops those that do not fit and gives the others their measurement. Places pass.
/// `moved`, when given, holds per object the rigid motion (global frame) a solve applied to it
/// after the alignment: its vertices and node are moved by it before ICP, rotation included, so
/// an alignment's yaw error that the solve corrected does not turn one copy against the other.
std::vector<MergeCandidate> refineObjectMerges(
    std::vector<MergeCandidate> candidates, const SceneGraph& frontend,
    const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const std::map<RobotId, const Mesh*>& meshes, const ReconciliationOptions& options = {},
    const std::map<NodeId, Eigen::Isometry3d>* moved = nullptr);

/// The merge factors: ICP's measurement where there is one, else zero translation (with the
/// rotation the alignment gives, weighted unmeasured_rotation_variance).
std::vector<PoseGraphEdge> mergeFactors(const std::vector<MergeCandidate>& candidates,
                                        const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
                                        const ReconciliationOptions& options = {});

/// Two copies of one object with different labels, and which label the vote gave it.
struct LabelDispute {
  NodeId winner, loser;  ///< the loser merges into the winner, whose label the object keeps
  double odds = 1.0;     ///< of the winner's label over the loser's
};

/// The label disputes among the objects of `graph` (the backend graph: global frame, each object's
/// mesh_vertices indexing graph.mesh()); `voters` holds, per object, the robots whose copies it
/// unites (an object not in it: the robot of its id). Each object takes part in one dispute at
/// most, nearest pairs first.
std::vector<LabelDispute> resolveLabelDisputes(const SceneGraph& graph,
                                               const std::map<NodeId, std::set<RobotId>>& voters,
                                               const ReconciliationOptions& options = {});

}  // namespace hydra_multi
