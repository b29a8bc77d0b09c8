#pragma once
// SE(3) pose-graph optimization: rotations on a quaternion manifold, translations in R^3, Ceres'
// residuals. Sparse Cholesky solves run our Levenberg-Marquardt on CHOLMOD
// (sparse_levenberg_marquardt.h), conjugate gradients run Ceres. Each edge may carry a weight (the
// GNC weights of gnc.h); the problem, and its sparse analysis, stay between solves, so GNC
// re-solves only change weights.
//
// Gauge: the cost is invariant to one global rigid transform, so one pose (the anchor) is held
// constant; without that the normal equations are singular.

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/optim/pose_graph.h"

namespace hydra_multi {

class SparseAnalyses;

enum class ResidualType { kGeodesic, kChordal };
const char* residualTypeName(ResidualType type);

struct PoseGraphOptimizerOptions {
  ResidualType residual = ResidualType::kGeodesic;
  int max_iterations = 100;  ///< Levenberg-Marquardt iterations per solve
  /// Relative cost change that ends a solve (docs/DECISIONS.md "The backend's solves stop at a
  /// relative cost change of 1e-4, not 1e-3").
  double function_tolerance = 1e-4;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
  int num_threads = 1;  ///< Ceres' threads (conjugate gradients)
  /// Threads that linearize and factorize the sparse Cholesky solves (LmOptions::threads; the
  /// same steps as one thread's, to the bit).
  int linearization_threads = 1;
  /// Sparse Cholesky: a factorization of at least this many flops in single precision, its
  /// solve refined once in double (LmOptions::single_precision_from_flops); negative: never.
  double single_precision_from_flops = -1.0;
  /// Sparse Cholesky is exact and fast while the graph stays sparse; outlier loop closures that
  /// join random poses make its factor dense, where Jacobi-preconditioned conjugate gradients (no
  /// fill-in) are the only affordable step (docs/DECISIONS.md "Conjugate gradients by the
  /// factor's fill, not by a timed iteration").
  enum class LinearSolver {
    kSparseCholesky,
    kConjugateGradients
  } linear_solver = LinearSolver::kSparseCholesky;
  int max_linear_iterations = 200;  ///< for conjugate gradients
  bool verbose = false;             ///< Ceres' per-iteration log on stderr
  /// Sparse Cholesky: an analysis made ahead (SparseAnalyses, sparse_levenberg_marquardt.h) that a
  /// problem of its pattern takes instead of analyzing its own; with keep_analysis, a problem
  /// leaves its own there when it ends (a problem prepared on another thread: max_iterations 0).
  std::shared_ptr<SparseAnalyses> analyses;
  bool keep_analysis = false;
};

struct SolveSummary {
  bool usable = false;  ///< Ceres returned a usable solution
  std::string message;
  int iterations = 0;
  double initial_cost = 0;  ///< Ceres' cost: 1/2 sum of weighted squared residuals
  double final_cost = 0;
  double time_s = 0;
  /// Sparse Cholesky: of time_s, the numeric factorizations; and before the solve, the analysis
  /// of the problem's pattern (its ordering and symbolic factorization) since the last solve.
  double factorization_s = 0;
  double analysis_s = 0;
  /// Factorizations in single precision, and those that failed in it and were made in double.
  int single_precision_factorizations = 0, single_precision_fallbacks = 0;
};

/// Where solves' time went, summed over them (SolveSummary): in Levenberg-Marquardt, of it in the
/// numeric factorizations, and in the analyses of the problems' patterns before them.
struct SolverTime {
  double solve_s = 0.0, factorization_s = 0.0, analysis_s = 0.0;
  int iterations = 0;  ///< Levenberg-Marquardt iterations (steps tried)
  SolverTime& operator+=(const SolveSummary& s) {
    solve_s += s.time_s;
    iterations += s.iterations;
    factorization_s += s.factorization_s;
    analysis_s += s.analysis_s;
    return *this;
  }
  SolverTime& operator+=(const SolverTime& o) {
    solve_s += o.solve_s;
    iterations += o.iterations;
    factorization_s += o.factorization_s;
    analysis_s += o.analysis_s;
    return *this;
  }
};

class PoseGraphProblem {
 public:
  /// Builds the problem over every edge whose endpoints have an initial pose. Edges with a missing
  /// endpoint are left out (edgeIncluded() tells).
  PoseGraphProblem(const PoseGraph& graph, const std::map<NodeId, Eigen::Isometry3d>& initial,
                   NodeId anchor, const PoseGraphOptimizerOptions& options = {});
  ~PoseGraphProblem();
  PoseGraphProblem(const PoseGraphProblem&) = delete;
  PoseGraphProblem& operator=(const PoseGraphProblem&) = delete;

  /// Changes how later solves run (iterations, tolerances, linear solver); the problem stays.
  void setOptions(const PoseGraphOptimizerOptions& options);
  const PoseGraphOptimizerOptions& options() const;

  /// Per-edge weights in [0, 1] (one per graph edge; 1 by default).
  void setWeights(const std::vector<double>& weights);
  SolveSummary solve();
  /// Puts every pose back at its initial value.
  void resetToInitial();
  /// Moves the poses it has to `poses` (the others stay).
  PoseGraphProblem& setPoses(const std::map<NodeId, Eigen::Isometry3d>& poses);
  /// Holds these poses constant in later solves, as the anchor (a local solve); replaces the set
  /// given before.
  PoseGraphProblem& holdConstant(const std::set<NodeId>& ids);

  /// Per graph edge (shorter: the rest are in): edges left out of the problem, as if excluded,
  /// until a later call brings them back. For factors at weight 0 for a while (held out of
  /// GNC): out of the sparse factor's pattern, they cost it no fill-in. One given a weight > 0
  /// comes back on the next solve. A change makes the next solve order and analyze anew.
  PoseGraphProblem& leaveOut(const std::vector<bool>& edges);

  std::map<NodeId, Eigen::Isometry3d> poses() const;
  /// The same poses written into `poses`: in place where it holds exactly the problem's nodes (no
  /// allocation), made anew otherwise.
  void posesInto(std::map<NodeId, Eigen::Isometry3d>& poses) const;
  /// Unweighted squared residual of every edge at the current poses (0 for excluded edges):
  /// the squared Mahalanobis norm for geodesic residuals, the chordal cost term for chordal ones.
  std::vector<double> squaredResiduals() const;
  bool edgeIncluded(size_t edge) const;
  /// Floating-point operations of one sparse Cholesky factorization per free pose (the ordering
  /// and analysis are made here if no solve made them yet): how much the factor fills in.
  double choleskyFlopsPerPose();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The SE-Sync objective F (data/README.md) of the given edges at the given poses; edges with a
/// missing endpoint count as missing, not as zero (they make it fail).
Result<double> sesyncCost(const std::vector<PoseGraphEdge>& edges,
                          const std::map<NodeId, Eigen::Isometry3d>& poses);

}  // namespace hydra_multi
