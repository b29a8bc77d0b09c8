#pragma once
// One backend round (paper III-B, DESIGN.md "Data flow"): from the frontend's state to the
// backend graph, optimized and in one global frame (robot `root`'s):
//   1. align: InitialAlignment of the robots from the inter-robot loop closures, by maximum
//      consensus per robot pair (initial_alignment.h);
//   2. proposeOnLoopClosureSolve: the deformation graph of the aligned robots without merges,
//      its skeleton solved with GNC, loop closures outside their pair's consensus held out (they
//      come back only where they fit the result; deformation_graph.h); reconciliation proposals
//      on that solution as merge factors (reconciliation.h);
//   3. the graph with the merge factors, held out in the same way, solved again (GNC on the
//      skeleton, then the whole graph once) from startWithMerges, the loop closures taken as
//      step 2 decided them (known inliers, or held out to be taken back where they fit);
//   4. the backend graph (optimized_map.h: unplacedMap, made on a second thread while steps 2
//      and 3 solve, startBackendGraph; then placeBackendGraph), and the merges GNC kept or none
//      (node_merging.h), made in it on that thread while the whole graph is solved, their
//      positions fused once it is placed; those threads, and the one that keeps what the next
//      round starts from, run at the lowest priority (core/background_task.h) beside the solve's;
//   5. rooms segmented over the optimized places (room_segmentation.h).
// Robots not aligned yet are left out of the backend graph until they are. Incremental rounds
// (BackendOptions::incremental) start GNC where the last round ended (round_memory.h); a robot
// whose alignment changed starts afresh. Merges are proposed anew every round (ICP's verdict on
// an object pair reused while the pair keeps its relative placement, IcpCache), and one kept
// before is decided again when the result contradicts it, so a merge later rounds no longer
// support is undone.
// docs/DECISIONS.md: "Factors held out of GNC", "Rounds start where the last one ended".

#include <future>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/backend/initial_alignment.h"
#include "hydra_multi/backend/node_merging.h"
#include "hydra_multi/backend/optimized_map.h"
#include "hydra_multi/backend/reconciliation.h"
#include "hydra_multi/backend/room_segmentation.h"
#include "hydra_multi/backend/round_memory.h"
#include "hydra_multi/core/background_release.h"
#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {

/// What the backend reads of one robot's frontend state (station ids, the robot's own frame).
struct BackendRobot {
  RobotId robot;
  const std::vector<PoseGraphEdge>* pose_graph = nullptr;
  const std::vector<ControlPoint>* control_points = nullptr;
  const std::vector<ControlPointEdge>* control_point_edges = nullptr;
  const Mesh* mesh = nullptr;
};

struct BackendOptions {
  InitialAlignmentOptions alignment;
  DeformationGraphOptions deformation;
  RoomSegmentationOptions rooms;
  ReconciliationOptions reconciliation;
  bool reconcile = true;
  bool segment_rooms = true;
  /// false (ablation no-ia): no initial alignment; every robot's own frame is taken as the
  /// global one and the deformation graph starts from there.
  bool initial_alignment = true;
  /// false (the paper's baselines): no joint optimization; each robot's graph is optimized alone
  /// with its own loop closures and placed by its alignment; no merges.
  bool joint_optimization = true;
  /// Inter-robot loop closures outside their pair's consensus (initial_alignment.h) start
  /// rejected in GNC and come back only if they fit its result.
  bool hold_out_alignment_outliers = true;
  /// Merge factors start rejected in GNC and are kept where they fit its result.
  bool hold_out_merges = true;
  /// Frames given from outside instead of estimated, T_global_robot (the gt-align baseline,
  /// evaluation only: the normal station never has them).
  std::map<RobotId, Eigen::Isometry3d> given_alignment;
  size_t mesh_neighbours = 4;  ///< control points that move a mesh vertex
  /// Each round starts where the last one ended: its GNC from the last round's poses (a node new
  /// since then moved as its robot's latest keyframe was), and the loop closures and merges it
  /// decided taken as decided (known inliers, or held out to be taken back where they fit), so
  /// GNC decides only the new ones and those the result contradicts; a robot whose alignment
  /// changed starts afresh. false: every round decides everything from the aligned frontend
  /// state, as the paper's batch backend.
  bool incremental = true;
  /// Incremental rounds: a merge new since the last round that fits the start of the solve with
  /// merges (its squared residual within GNC's threshold) is a known inlier there instead of held
  /// out, so no solve is spent without it; the solve still decides again a known inlier its
  /// result contradicts (RobustPgoOptions::known_inlier). The others stay held out.
  bool admit_fitting_merges = true;
  /// The merges GNC kept made in the backend graph on a second thread while the whole graph is
  /// solved (planMerges), their nodes' positions and boxes fused once the graph is placed
  /// (placeMerged); false: made after placing (mergeKept). The same graph either way.
  bool merge_while_solving = true;
  /// With merge_while_solving: the merges planned already while GNC solves with them, for the
  /// verdicts it reaches where it keeps every factor it starts with; planned again from a copy of
  /// the unplaced graph where GNC decides otherwise. The same graph either way.
  bool plan_merges_ahead = true;
  /// Incremental rounds: the loop closures' solve takes back, without solving again, a
  /// re-admission smaller than this share of its inlier edges once a solve has followed an earlier
  /// one (RobustPgoOptions::readmit_unsolved_share); the solve with merges solves them in. 0: every
  /// re-admission solved in, as in a round from scratch.
  double readmit_unsolved_share = 0.01;
  /// In incremental rounds the solve with merges does the same from its first re-admission on
  /// (RobustPgoOptions::readmit_unsolved_first); the whole-graph solve, then whole, solves them in.
  bool readmit_unsolved_with_merges = true;
};

struct BackendRoundReport {
  size_t robots = 0, robots_aligned = 0;
  /// Incremental rounds: aligned robots new or re-aligned since the last round, which start from
  /// their aligned frontend poses and have their inter-robot loop closures decided again.
  size_t robots_afresh = 0;
  size_t inter_robot_loop_closures = 0, inter_robot_inliers = 0;
  size_t merges_proposed = 0, merges_accepted = 0, merges_undone = 0;
  /// Objects merged by the label votes (reconciliation.h), not counted in merges_accepted.
  size_t label_merges = 0;
  size_t nodes = 0, rooms = 0;
  size_t variables = 0, factors = 0;  ///< poses and factors of the deformation graph
  double time_s = 0.0;
  /// Where the time went: alignment, proposals and graph assembly, the GNC solve, the solve of
  /// the whole deformation graph after it, the backend graph (mesh deformation, objects, merges),
  /// rooms.
  double alignment_s = 0.0, build_s = 0.0, gnc_s = 0.0, whole_graph_s = 0.0, graph_s = 0.0,
         rooms_s = 0.0;
  /// Of build_s: the loop closures' solve (its deformation graph built and solved without
  /// merges), and the merge candidates on it (proposals and their ICP).
  double loop_closure_solve_s = 0.0, candidates_s = 0.0;
  /// The round's pose-graph solves (the loop closures', GNC's with merges, the whole graph's):
  /// their time in Levenberg-Marquardt, of it the factorizations, and their analyses.
  SolverTime solver_time;
  /// Incremental rounds: robust factors (loop closures, merges) taken as decided from the last
  /// round, and those of them the solve contradicted and GNC decided again.
  size_t verdicts_known = 0, verdicts_redecided = 0;
  /// Merges new in this round taken as known inliers, as they fit the start (admit_fitting_merges).
  size_t merges_admitted = 0;
  int solves = 0;  ///< pose-graph solves of the round (GNC's included)
  /// Poses the whole-graph solve moved (DeformationGraphOptions::local_whole_graph: those near
  /// what changed since the last round; else all).
  size_t whole_graph_free = 0;
  /// The whole-graph solve took its analysis made ahead (whole_graph_analysis_ahead).
  bool whole_graph_ahead = false;
  /// The merges' plans made while solving (merge_while_solving; with plan_merges_ahead, 2 where
  /// GNC decided otherwise than expected).
  int merge_plans = 0;
  /// Mesh vertices the round deformed anew (MeshBinding; the others kept from the last round).
  size_t vertices_blended = 0;
  bool from_scratch = false;  ///< the round took nothing from the last one
};

/// A loop closure of a round and GNC's verdict on it: intra-robot ones from the robots' pose
/// graphs, inter-robot ones from the frontend's detector (keyframes in station ids).
struct LoopClosureVerdict {
  NodeId from, to;
  bool inter_robot = false;
  bool kept = false;
  bool operator==(const LoopClosureVerdict& o) const {
    return from == o.from && to == o.to && inter_robot == o.inter_robot && kept == o.kept;
  }
};

class Backend {
 public:
  explicit Backend(BackendOptions options = {})
      : options_(std::move(options)), alignment_([this] {
          InitialAlignmentOptions a = options_.alignment;
          a.always_realign = a.always_realign || !options_.joint_optimization;
          return a;
        }()) {}

  /// `support`: one weight per inter-robot loop closure for the alignment's consensus (empty:
  /// by count). `from_scratch`: take no poses or verdicts from the last round (as without
  /// BackendOptions::incremental) and estimate every alignment afresh (initial_alignment.h), so
  /// the result does not depend on when earlier rounds ran.
  BackendRoundReport round(const SceneGraph& frontend, const std::vector<BackendRobot>& robots,
                           const std::vector<PoseGraphEdge>& inter_robot, RobotId root,
                           const std::vector<double>& support = {}, bool from_scratch = false);

  const SceneGraph& graph() const { return graph_; }
  const InitialAlignment& alignment() const { return alignment_; }
  /// The robots in the last round's backend graph and their frames.
  const std::map<RobotId, RobotFrameAlignment>& aligned() const { return aligned_; }
  /// Per inter-robot loop closure (from, to) of the last round: kept by GNC.
  const std::map<std::pair<NodeId, NodeId>, bool>& loopClosureInliers() const { return inliers_; }
  /// The merges of the last round.
  const std::vector<AcceptedMerge>& merges() const { return merges_; }
  /// Every loop closure of the aligned robots in the last round, intra- and inter-robot, with
  /// GNC's verdict (those GNC did not see, of robots not aligned yet, are left out).
  const std::vector<LoopClosureVerdict>& loopClosures() const { return verdicts_; }

 private:
  // The aligned robots as the deformation graph takes them.
  struct Team {
    std::vector<RobotDeformationInput> inputs;
    std::map<RobotId, Eigen::Isometry3d> T_global_robot;
    std::map<RobotId, const Mesh*> meshes;
    /// The control points `inputs` point to where the station takes fewer than the robots sent
    /// (DeformationGraphOptions::control_point_voxel); a map, so that moving a Team keeps them.
    std::map<RobotId, ControlPointGraph> coarse;
  };
  struct Proposals {
    std::vector<MergeCandidate> candidates;
    DeformationWarmStart solved;  ///< the loop closures' solve, for the solve with merges
    /// That solve's solution before it re-admitted loop closures (empty: it re-admitted none).
    std::map<NodeId, Eigen::Isometry3d> held_out;
  };

  void align(const SceneGraph& frontend, const std::vector<BackendRobot>& robots,
             const std::vector<PoseGraphEdge>& inter_robot, RobotId root,
             const std::vector<double>& support);
  Team alignedTeam(const std::vector<BackendRobot>& robots) const;
  /// Inter-robot loop closures the alignment's consensus rejected: held out of GNC.
  std::set<std::pair<NodeId, NodeId>> alignmentOutliers() const;
  /// RoundMemory::lastRound for the robots of `team`, in an incremental round (else nothing).
  DeformationWarmStart lastRound(
      const DeformationGraph& graph, const Team& team,
      std::map<NodeId, Eigen::Isometry3d>* last_proposal = nullptr,
      std::map<NodeId, Eigen::Isometry3d>* last_held_out = nullptr) const {
    if (!incremental()) return {};
    return memory_.lastRound(graph, team.T_global_robot, last_proposal, last_held_out);
  }
  bool incremental() const { return options_.incremental && !from_scratch_; }
  /// The deformation graph without merges solved (its skeleton), and the merge candidates
  /// proposed and checked on that solution.
  Proposals proposeOnLoopClosureSolve(const SceneGraph& frontend, const Team& team,
                                      const std::vector<PoseGraphEdge>& loop_closures,
                                      const std::set<std::pair<NodeId, NodeId>>& held_out,
                                      BackendRoundReport& report) const;
  void recordVerdicts(const Team& team, const std::vector<PoseGraphEdge>& inter_robot,
                      const DeformationResult& result, BackendRoundReport& report);
  /// Where the solve with merges starts (step 3): the loop closures' solve `solved` and the
  /// verdicts it made (the loop closures it kept leave `held_out`), in an incremental round moved
  /// as the last round's solve with merges was and with the last round's verdicts on the merges;
  /// without that solve, the last round's.
  DeformationWarmStart startWithMerges(const DeformationGraph& graph, const Team& team,
                                       DeformationWarmStart solved,
                                       const std::vector<PoseGraphEdge>& merges,
                                       std::set<std::pair<NodeId, NodeId>>& held_out,
                                       BackendRoundReport& report) const;
  /// The backend graph made on second threads while the deformation graphs are solved: its nodes,
  /// edges and mesh, which need no pose (unplacedMap; with `spare`, a copy of it too), and then
  /// the merges GNC kept in it (planMerges, by planMergesFor).
  struct MapInProgress {
    std::future<SceneGraph> unplaced, spare;
    std::future<std::pair<SceneGraph, MergePlan>> planned;
    std::vector<bool> planned_kept;  ///< per candidate, made in `planned`
    int plans = 0;                   ///< started
  };
  MapInProgress startBackendGraph(const SceneGraph& frontend, const Team& team, bool spare) const;
  /// Starts planning the merges of `candidates` that `verdicts` keep in `made`'s graph, unless
  /// `made` plans just those already (from the spare copy where it plans others).
  void planMergesFor(const SceneGraph& frontend, const Team& team,
                     const std::vector<MergeCandidate>& candidates, const RobustVerdicts& verdicts,
                     MapInProgress& made) const;
  /// Step 4: that graph placed by the solve (placeMap) with the merges GNC kept (placeMerged, or
  /// mergeKept where the plan cannot be used), the mesh deformed where control points moved.
  SceneGraph placeBackendGraph(const SceneGraph& frontend, const Team& team,
                               const DeformationGraph& graph, const DeformationResult& result,
                               const std::vector<MergeCandidate>& candidates, MapInProgress& made,
                               BackendRoundReport& report);

  BackendOptions options_;
  // What a round is done with (its deformation graphs, warm starts, the last backend graph),
  // freed on a second thread at the round's end.
  mutable BackgroundRelease spent_;
  InitialAlignment alignment_;
  std::map<RobotId, RobotFrameAlignment> aligned_;
  SceneGraph graph_;
  std::map<RobotId, Eigen::Isometry3d> optimized_first_keyframes_;
  std::map<std::pair<NodeId, NodeId>, bool> inliers_;
  std::vector<AcceptedMerge> merges_;
  std::vector<LoopClosureVerdict> verdicts_;
  bool from_scratch_ = false;   // this round's
  RoundMemory memory_;          // what the next round starts from (BackendOptions::incremental)
  mutable IcpCache icp_cache_;  // ICP's verdicts on object pairs, for incremental rounds
  std::map<RobotId, MeshBinding> mesh_bindings_;  // each robot's mesh, for incremental rounds
};

}  // namespace hydra_multi
