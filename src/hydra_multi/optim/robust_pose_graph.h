#pragma once
// Pose-graph optimization with or without GNC-TLS over the loop closures (eq. (3) of the paper,
// solved robustly as in Hydra-Multi): odometry edges are known inliers; every loop-closure edge is
// a robust factor whose weight GNC drives to 0 (outlier) or 1 (inlier).

#include <functional>
#include <map>
#include <set>
#include <string>

#include "hydra_multi/optim/gnc.h"
#include "hydra_multi/optim/pose_graph_optimizer.h"

namespace hydra_multi {

struct RobustPgoOptions {
  PoseGraphOptimizerOptions solver;
  bool robust = true;  ///< GNC over loop closures; false: one least-squares solve
  GncOptions gnc;
  /// Start every GNC solve from the initial values (GTSAM's choice) instead of the previous
  /// solution (warm start, the default).
  bool restart_from_initial = false;
  /// Outlier loop closures join random poses, and the sparse Cholesky factor of a pattern that
  /// holds them fills in.
  /// When one factorization takes more than this many MFLOP per free pose (CHOLMOD's analysis of
  /// the pattern: fixed, whatever the load of the machine), the GNC solves use conjugate
  /// gradients, and the result is polished by one Cholesky solve over the known inliers and the
  /// loop closures GNC kept (sparse again). 0 forces conjugate gradients; a huge value forces
  /// Cholesky. docs/DECISIONS.md: "Conjugate gradients by the factor's fill, not by a timed
  /// iteration".
  double cholesky_mflops_per_pose_limit = 2.0;
  /// After GNC, loop closures it rejected whose squared residual at the final solution is within
  /// the inlier threshold are taken back and the inliers re-solved, until nothing changes. GNC is
  /// local: on CSAIL it ended with 12 of 128 true closures rejected that all fit its own solution.
  bool readmit_consistent = true;
  /// A re-admission smaller than this share of the inlier edges, after the solve that followed an
  /// earlier one, is taken back without solving again: the result is then the optimum without
  /// those few, which fit it, and a later solve over them is left to solve them in (0: every
  /// re-admission is solved in).
  double readmit_unsolved_share = 0.0;
  /// The share applies to the first re-admission too: for a solve whose result a later solve
  /// over the same factors starts from (RobustPgoResult::readmitted_unsolved names them).
  bool readmit_unsolved_first = false;
  /// When GNC stopped on its weights (each within GncOptions::weight_tolerance of 0 or 1) and its
  /// last solve's Levenberg-Marquardt stopped before gnc_inner_iterations, that solution stands as
  /// the first solve over the inliers: it is their optimum to the weight tolerance and the solver's
  /// own, and the re-admission test starts from it. false: the inliers are solved again.
  bool keep_converged_gnc_solve = false;
  /// Levenberg-Marquardt iterations of each GNC solve (0: solver.max_iterations). GNC re-weights
  /// after every solve, so inner solves need not converge, and short ones keep GNC near a good
  /// initial estimate while the loop-closure weights are still small (docs/DECISIONS.md "Three
  /// iterations per GNC solve in the station, not one").
  int gnc_inner_iterations = 3;
  /// GNC's mu step (GncOptions::mu_step) when at least as many robust factors are known inliers as
  /// are undecided: an incremental round deciding what is new beside what earlier rounds kept.
  /// 1: gnc.mu_step throughout. docs/DECISIONS.md: "GNC's incremental step 6, not 3".
  double incremental_mu_step = 6.0;
  /// GNC's first weights from the residuals at the initial estimate instead of a least-squares
  /// solve over every loop closure (see runGnc).
  bool gnc_from_initial_estimate = true;
  /// Per graph edge (empty: none): robust factors GNC holds out, at weight 0 throughout and out of
  /// the sparse factor's pattern (PoseGraphProblem::leaveOut); they count as rejected, and
  /// readmit_consistent takes back those that fit the result. For loop closures an earlier, more
  /// global test already doubts (the alignment's consensus, initial_alignment.h). In a solve that
  /// is not robust nothing takes them back: they are no part of it, as if absent from the graph
  /// (a solve over part of a large graph without a copy of the rest), and count as rejected.
  std::vector<bool> held_out;
  /// Per graph edge (empty: none): robust factors known to be inliers (an earlier solve's verdict),
  /// at weight 1 while GNC decides the others. One whose squared residual at GNC's result exceeds
  /// the inlier threshold is no longer taken as known: GNC runs again with it among the undecided
  /// (RobustPgoResult::known_contradicted counts them). With every robust factor known or held out,
  /// GNC has nothing to decide and the result is the polish and re-admission alone.
  std::vector<bool> known_inlier;
  /// An earlier solve of about the same problem (RobustPgoResult::held_out_poses and poses): each
  /// solve after a re-admission starts from this one's held-out solution H moved as the earlier
  /// re-admissions moved it, H_now H_then^-1 F_then (nodes in all three), when that fits the
  /// inliers better than the solution before the re-admission (else from that solution).
  std::map<NodeId, Eigen::Isometry3d> earlier_held_out, earlier_readmitted;
  /// Poses held where `initial` puts them, as the anchor: a local solve of the others.
  std::set<NodeId> constant;
  /// In a robust solve whose poses are at least chain_min_share chain interiors (poses with two
  /// edges, both known inliers), GNC and its polish run with each chain reduced to one composed
  /// edge; the interiors are then placed and everything polished by one solve over the inliers
  /// (pose_graph_chains.h). The result is that solve's optimum; GNC's decisions are taken on the
  /// reduced graph. docs/DECISIONS.md: "Chains solved as one edge while GNC decides".
  bool reduce_chains = true;
  double chain_min_share = 0.3;
  /// Called after every solve with a one-line report (for progress output on long runs).
  std::function<void(const std::string&)> progress;
};

struct RobustPgoResult {
  std::map<NodeId, Eigen::Isometry3d> poses;
  std::vector<bool> edge_inlier;    ///< per graph edge: odometry true, loop closures by GNC
  std::vector<double> edge_weight;  ///< final GNC weight per edge (1 for odometry)
  GncResult gnc;                    ///< empty when not robust
  /// The solution of the first polish (rejected and held-out factors at weight 0) when loop
  /// closures that fit it were re-admitted after it; empty otherwise.
  std::map<NodeId, Eigen::Isometry3d> held_out_poses;
  int solves = 0;
  SolverTime solver_time;         ///< over all solves (their time and iterations)
  size_t known_contradicted = 0;  ///< known inliers GNC had to decide again (known_inlier)
  /// Factors taken back as fitting the result without a solve after (readmit_unsolved_share):
  /// their graph edges.
  std::vector<size_t> readmitted_unsolved;
  double final_cost = 0.0;  ///< Ceres cost of the last solve (weighted)
  double time_s = 0.0;
  bool usable = true;
  std::string message;  ///< the last solve's report
};

/// The edges among `candidates` (indices into `graph`) with both ends in `poses` whose squared
/// residual there is within GNC's inlier threshold (options.gnc): those a solve takes back.
std::vector<size_t> edgesThatFit(const PoseGraph& graph, const std::vector<size_t>& candidates,
                                 const std::map<NodeId, Eigen::Isometry3d>& poses, NodeId anchor,
                                 const RobustPgoOptions& options);

RobustPgoResult optimizePoseGraph(const PoseGraph& graph,
                                  const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                                  const RobustPgoOptions& options = {});

}  // namespace hydra_multi
