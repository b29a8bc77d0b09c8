#pragma once
// Reconciliation proposals (paper III-B): nodes of different aligned robots that look like one.
//   places   centres within place_max_distance and radii within place_max_radius_difference;
//   objects  the same label and overlapping bounding boxes (either box holds the other's
//            centre; Hydra's test).
// Matching nodes are grouped, nearest pairs first, at most one node of each robot in a group;
// every other node of a group merges into the group's node of the lowest robot index.
// Object candidates are then checked by ICP of the source object's mesh vertices onto the
// target's (refineObjectMerges, registration/icp.h): a pair whose surfaces do not fit (too few
// vertices paired, too large an error, the copy moved too far) is dropped; a fit that turns the
// copy more than icp_max_rotation_deg is taken for a wrong fit of two partial surfaces and the
// pair keeps the plain factor; for the others ICP's transform gives the merge factor's
// measurement. Each candidate becomes a robust factor of the deformation graph
// (deformation_graph.h): the relative pose ICP found, or for places (and objects without
// vertices or ICP's measurement) the two nodes at one position. The backend proposes on the map
// its loop closures optimized and holds the factors out of GNC, keeping those that fit its result
// (backend.h); node_merging.h makes the kept ones, or none when fewer than min_valid_share were
// kept (the paper's undo). Proposals are made anew every round, so a merge is taken back whenever
// a later round no longer supports it.
//
// Label votes (beyond the paper; off by default, `reconciliation.label_votes`): where two robots
// label one object differently the team's graph keeps both copies. resolveLabelDisputes finds
// such pairs in the backend graph after the merges: objects of different robots and labels whose
// boxes overlap (as above) and whose deformed mesh vertices coincide (most of the smaller
// object's vertices within label_vertex_distance_m of the other's: one surface, not a chair under
// a table). The label follows Bayes with a confusion of label_confusion per robot, the same
// between any two labels: the odds of label A over B are
//   (n_A + 1) / (n_B + 1) * ((1 - p) / p)^(k_A - k_B),
// n the objects of that label in the team's graph (the prior), k the robots that gave it. A pair
// whose odds reach label_min_odds either way merges into the winner; others stay as they are.
// docs/DECISIONS.md: "Places merge within 0.3 m", "Copies grouped, not paired", "A wrong ICP fit
// keeps the plain factor", "Label votes off by default".

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
  /// holds positions only (a place has no orientation).
  double unmeasured_rotation_variance = 1e4;
  /// ICP of object candidates: kept when at least this share of the source's vertices pair
  /// with the target's within the correspondence distance, with at most this error, moving the
  /// source's vertex centroid at most icp_max_shift_m and turning it at most
  /// icp_max_rotation_deg (a larger turn: the plain factor).
  bool object_icp = true;
  double icp_min_paired_share = 0.5;
  double icp_max_rmse_m = 0.2;
  double icp_max_shift_m = 1.0;
  double icp_max_rotation_deg = 20.0;
  size_t icp_min_vertices = 8;  ///< fewer on either side: no ICP, the plain factor
  int icp_threads = 2;  ///< threads that run the candidates' ICP (each fit is its pair's alone)
  /// An object pair whose relative placement moved less than this (metres and radians) since
  /// ICP last checked it takes that check's verdict (IcpCache).
  double icp_reuse_m = 0.01;
  double icp_reuse_rad = 0.01;
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
/// robots' copies of a place. The places' candidates come first, then the objects'; `only` (kPlaces
/// or kObjects) gives those of one layer alone, the same as in the full list.
std::vector<MergeCandidate> proposeMerges(
    const SceneGraph& frontend, const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const ReconciliationOptions& options = {},
    const std::map<NodeId, Eigen::Vector3d>* optimized = nullptr,
    std::optional<Layer> only = std::nullopt);

/// ICP's verdicts on object pairs (target, source), kept for the next check. ICP's result, the
/// checks on it and the factor's measurement depend only on the two objects' vertices and how they
/// are placed relative to each other; a pair whose objects kept their vertices and whose relative
/// placement moved less than icp_reuse_m and icp_reuse_rad since ICP ran on it takes that
/// verdict without ICP.
struct IcpCache {
  struct Entry {
    double target_key = 0.0, source_key = 0.0;  ///< the objects' vertices (count and sums)
    Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  ///< X_target^-1 X_source
    bool kept = false;
    std::optional<Eigen::Isometry3d> T_target_source;
  };
  std::map<std::pair<NodeId, NodeId>, Entry> entries;
  size_t reused = 0, computed = 0;  ///< pairs of the last check
};

/// Checks the object candidates by ICP on their mesh vertices (`meshes`: each robot's, in its own
/// frame); drops those that do not fit and gives the others their measurement. Places pass.
/// `moved`, when given, holds per object the rigid motion (global frame) a solve applied to it
/// after the alignment: its vertices and node are moved by it before ICP, rotation included, so
/// an alignment's yaw error that the solve corrected does not turn one copy against the other.
/// `cache`, when given, is read and updated (IcpCache; pairs not among the candidates leave it).
std::vector<MergeCandidate> refineObjectMerges(
    std::vector<MergeCandidate> candidates, const SceneGraph& frontend,
    const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const std::map<RobotId, const Mesh*>& meshes, const ReconciliationOptions& options = {},
    const std::map<NodeId, Eigen::Isometry3d>* moved = nullptr, IcpCache* cache = nullptr);

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
