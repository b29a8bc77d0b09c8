#pragma once
// The embedded deformation graph of the whole team (paper III-B, eq. 3; Sumner 2007, Kimera-PGMO),
// as one SE(3) pose graph solved robustly (optim/robust_pose_graph.h, GNC with TLS):
//   nodes    every aligned robot's keyframes, mesh control points (the first of each voxel of
//            control_point_voxel), places and the objects of merge candidates, initialized in the
//            global frame through the robot's alignment (initial_alignment.h);
//   factors  known inliers: odometry, mesh rigidity between connected control points, links from
//            keyframes to the control points they observed, links from places (and objects) to
//            their nearest control point (or keyframe); robust: the robots' own loop closures,
//            inter-robot loop closures and merge candidates (ReconciliationProposals), all under
//            GNC.
// The ties the station makes from one robot's map (rigidity, the links of places and objects,
// a mesh vertex's control points) join only what the robot made within link_max_dt_s of each
// other. Every factor's information is 1/variance on every axis with Kimera-PGMO's variances
// (odometry 1e-2, its rotation 1e-4; loop closures 5e-2; mesh 1e-2), not the information the
// robots send (use_sent_information). GNC runs on the graph's skeleton (keyframes with their
// odometry, every robust factor, places and objects linked to their nearest keyframe), then the
// whole graph is solved once with the factors GNC kept (two_stage); started from an earlier
// round's solution, that solve moves only the nodes of factors whose two poses the skeleton placed
// otherwise relative to each other, and their neighbours (local_whole_graph). docs/DECISIONS.md:
// "Ties only between what a robot made within 10 s", "Kimera-PGMO's variances, not the robots'
// information", "GNC on the skeleton, then the whole graph once", "The whole-graph solve moves
// only what changed".
//
// After the solve, the mesh moves with its control points (mesh_deformation.h).

#include <functional>
#include <map>
#include <set>
#include <vector>

#include "hydra_multi/dsg/mesh.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"
#include "hydra_multi/optim/robust_pose_graph.h"

namespace hydra_multi {

/// What the deformation graph needs of one robot: its frontend state, in station ids.
struct RobotDeformationInput {
  RobotId robot;
  Eigen::Isometry3d T_global_robot = Eigen::Isometry3d::Identity();
  const std::vector<PoseGraphEdge>* pose_graph = nullptr;  ///< odometry, own loop closures
  const std::vector<ControlPoint>* control_points = nullptr;
  const std::vector<ControlPointEdge>* control_point_edges = nullptr;
  const Mesh* mesh = nullptr;  ///< its mesh, for the time of an object's vertices (madeAtNs)
};

/// When a robot placed a node in its map, for the ties of about that time (link_max_dt_s): an
/// object by its mesh vertices (the median of their times), as Hydra computes an object from its
/// vertices, which may be of an earlier pass than the object's last update; any other node at its
/// last update.
int64_t madeAtNs(const Node& node, const Mesh* mesh);

struct DeformationGraphOptions {
  double odometry_variance = 1e-2;
  double loop_closure_variance = 5e-2;
  double mesh_variance = 1e-2;
  /// What the station ties together from one robot's map (two control points by mesh rigidity, a
  /// place or object and the keyframe or control point it is linked to, a mesh vertex and the
  /// control points it moves with) was made by the robot at most this far apart in time (s;
  /// core/nearest_neighbors.h TimedNeighbors; Kimera-PGMO's tol_t). <= 0: no limit.
  double link_max_dt_s = 10.0;
  bool use_sent_information = false;
  double place_link_radius = 3.0;  ///< m: a place links to a control point this close, else
                                   ///< to its nearest keyframe
  /// Chains not reduced (RobustPgoOptions::reduce_chains): docs/DECISIONS.md "Chains solved as
  /// one edge while GNC decides". Two threads linearize (LmOptions::threads): docs/DECISIONS.md
  /// "The linearization on two threads". GNC's converged last solve kept as the solve over the
  /// inliers (RobustPgoOptions::keep_converged_gnc_solve): docs/DECISIONS.md "GNC's last solve
  /// kept where it converged".
  RobustPgoOptions solver = [] {
    RobustPgoOptions options;
    options.reduce_chains = false;
    options.solver.linearization_threads = 2;
    options.solver.single_precision_from_flops = 1e8;
    options.keep_converged_gnc_solve = true;
    return options;
  }();
  bool two_stage = true;  ///< GNC on the skeleton, then one solve of the whole graph
  /// Rotation variance of the odometry, in both solves (its translation's is odometry_variance).
  double odometry_rotation_variance = 1e-4;
  /// Levenberg-Marquardt iterations of that whole-graph solve; 0: none, control points move
  /// rigidly with the keyframe that observed them.
  int final_iterations = 10;
  /// A whole-graph solve that starts from an earlier one (DeformationWarmStart::last_whole) moves
  /// only what changed: the nodes new since then or that the warm start moved (the skeleton moved
  /// them) by more than local_move_m or local_move_rad, and those within local_hops edges of
  /// them; the others stay where the earlier solution put them. When that is more than
  /// local_max_share of the nodes, the whole graph is solved. false: always the whole graph.
  bool local_whole_graph = true;
  double local_move_m = 1e-3;
  double local_move_rad = 1e-3;
  int local_hops = 1;
  double local_max_share = 0.5;
  /// Where more than local_max_share but at most local_deferred_share of the nodes changed, the
  /// solve stays local and the next round owes a whole one (DeformationResult::
  /// whole_graph_deferred, DeformationWarmStart::whole_owed): a round where much of the graph
  /// moved hands the whole solve on to the next. At most local_max_share: none deferred.
  double local_deferred_share = 0.6;
  /// The whole-graph solve's sparse analysis (ordering, symbolic factorization) made on a second
  /// thread while GNC solves the skeleton, for the factors GNC is expected to keep (every robust
  /// factor it starts with, and the merges it holds out, which it takes back where they fit; not
  /// the loop closures it holds out); the solve takes it where GNC kept just those, and analyzes
  /// its own otherwise. The same solve either way, to the bit. A local solve (local_whole_graph)
  /// does not wait for it: it stops at its next step. Off by default: beside the station's
  /// frontend the second thread slowed more than it saved (docs/DECISIONS.md).
  bool whole_graph_analysis_ahead = false;
  /// The station's control points: of each robot's, the first in each voxel of this size (m; in
  /// the robot's frame), with the rigidity edges of the others carried over to them
  /// (coarserControlPoints); <= 0: every control point the robots send (Hydra's: one per 2.5 m
  /// voxel). docs/DECISIONS.md: "Control points on a 5 m grid in the station".
  double control_point_voxel = 5.0;
};

/// The control point node id of robot r's control point `index`.
NodeId controlPointId(RobotId robot, uint64_t index);

/// A robot's control points on a coarser voxel grid: of `points` (in the order the robot made
/// them), the first in each voxel of `voxel` m; every edge of `edges` joins the kept points of its
/// two ends' voxels instead (once; none within one voxel). A point later in a voxel never
/// replaces its first, so the result only grows as the robot adds points.
struct ControlPointGraph {
  std::vector<ControlPoint> points;
  std::vector<ControlPointEdge> edges;
};
ControlPointGraph coarserControlPoints(const std::vector<ControlPoint>& points,
                                       const std::vector<ControlPointEdge>& edges, double voxel);

struct DeformationGraph {
  PoseGraph graph;                              ///< every factor (its nodes: `initial`)
  PoseGraph skeleton;                           ///< keyframes, places, objects; robust factors
  std::map<NodeId, NodeId> observed_by;         ///< control point -> keyframe that observed it
  std::map<NodeId, Eigen::Isometry3d> initial;  ///< global frame, before optimization
  NodeId anchor;                                ///< the root robot's first keyframe
  size_t robust_factors = 0, inter_robot_factors = 0;
  std::set<std::pair<NodeId, NodeId>> merge_factors;  ///< the robust factors that are merges
  bool whole = true;  ///< false: assembled only as far as the skeleton (`graph` empty)
};

/// Assembles the deformation graph of the aligned robots. `frontend` holds every robot's nodes in
/// its own frame; `inter_robot` and `merges` are robust factors between station ids. For a solve
/// that stops at the skeleton (two_stage, final_iterations 0) `graph` is left without factors:
/// `initial` and `observed_by` still hold every node.
DeformationGraph buildDeformationGraph(const SceneGraph& frontend,
                                       const std::vector<RobotDeformationInput>& robots,
                                       const std::vector<PoseGraphEdge>& inter_robot,
                                       const std::vector<PoseGraphEdge>& merges,
                                       const DeformationGraphOptions& options = {});

struct DeformationResult {
  std::map<NodeId, Eigen::Isometry3d> poses;                ///< optimized, global frame
  std::map<std::pair<NodeId, NodeId>, bool> robust_inlier;  ///< per robust factor (from, to)
  RobustPgoResult solve;        ///< GNC's solve (over the skeleton when two_stage)
  double whole_graph_s = 0.0;   ///< the whole-graph solve after it (two_stage)
  SolverTime solver_time;       ///< GNC's solves and the whole graph's
  size_t whole_graph_free = 0;  ///< poses that solve moved (local_whole_graph: not all)
  /// The whole-graph solve local though more than local_max_share changed: the next owes a whole
  /// one (local_deferred_share).
  bool whole_graph_deferred = false;
  size_t admitted = 0;  ///< held-out factors known as they fit the start (admit_if_fitting)
  /// The whole-graph solve took the analysis made ahead (whole_graph_analysis_ahead).
  bool whole_graph_analyzed_ahead = false;
};

/// What a solve may take from earlier ones: poses to start from instead of the graph's initial
/// ones, where it has them, and verdicts on robust factors (from, to): true, a known inlier that
/// GNC decides again only if its result contradicts it; false, held out (RobustPgoOptions).
/// `last_whole` and `last_skeleton`: an earlier round's solution of the whole graph and of its
/// skeleton. The robust solve starts a node `poses` lacks where the earlier whole solution had
/// it; the whole-graph solve starts a node there moved as the skeleton moved since
/// (S_now S_then^-1 W_then; a control point by its keyframe), so a round that changed little
/// starts at the earlier optimum. `held_out` and `readmitted`: an earlier robust solve's solution
/// without the factors it re-admitted and its final one (RobustPgoOptions::earlier_held_out).
struct DeformationWarmStart {
  std::map<NodeId, Eigen::Isometry3d> poses;
  std::map<std::pair<NodeId, NodeId>, bool> verdicts;
  std::map<NodeId, Eigen::Isometry3d> last_whole, last_skeleton;
  std::map<NodeId, Eigen::Isometry3d> held_out, readmitted;
  /// Held-out robust factors (from, to) that are known inliers where they fit the start (their
  /// squared residual at the start within GNC's threshold); the others stay held out.
  std::set<std::pair<NodeId, NodeId>> admit_if_fitting;
  /// The earlier round deferred its whole solve to this one: the whole graph is solved whole
  /// (DeformationGraphOptions::local_deferred_share).
  bool whole_owed = false;
};

/// `held_out`: robust factors (from, to) GNC starts without, taken back only if they fit its
/// result (RobustPgoOptions::held_out), whatever `warm` says of them (but admit_if_fitting).
/// `decided` (when given) is called with the result's robust_inlier as soon as GNC has decided
/// them, before the whole graph is solved; the result's are the same. `expected` (when given) is
/// called before GNC starts with the verdicts it reaches where it keeps every robust factor it
/// does not start without (those of `held_out`, those `warm` rejected).
using RobustVerdicts = std::map<std::pair<NodeId, NodeId>, bool>;
DeformationResult optimizeDeformationGraph(
    const DeformationGraph& graph, const DeformationGraphOptions& options = {},
    const std::set<std::pair<NodeId, NodeId>>& held_out = {},
    const DeformationWarmStart* warm = nullptr,
    const std::function<void(const RobustVerdicts&)>& decided = {},
    const std::function<void(const RobustVerdicts&)>& expected = {});

/// Nanoseconds of a window in seconds (<= 0: none).
inline int64_t windowNs(double seconds) {
  return seconds > 0.0 ? static_cast<int64_t>(seconds * 1e9) : 0;
}

}  // namespace hydra_multi
