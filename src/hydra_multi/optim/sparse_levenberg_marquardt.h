#pragma once
// Levenberg-Marquardt over SE(3) poses (rotation on a Ceres manifold, translation in R^3) with
// CHOLMOD's sparse Cholesky, for pose graphs whose factors change only their weights:
//   minimize  1/2 sum_k w_k ||r_k(x_i, x_j)||^2
//   step      (H + D / radius) delta = -g,  H = J^T W J,  g = J^T W r,  D = diag(H) clamped to
//             [1e-6, 1e32]; x <- x [+] delta (the manifold's Plus, tangent order [rotation, t])
//   radius    from 1e4, as Ceres' Levenberg-Marquardt strategy: a step is taken when
//             rho = actual / model decrease > 1e-3, then radius /= max(1/3, 1 - (2 rho - 1)^3);
//             else radius /= v, v *= 2. Stops on Ceres' function, gradient and parameter
//             tolerances, or after max_iterations steps (taken or not).
// Invariant: the sparsity of H (one 6x6 block per pose and per pair of poses a term joins, whatever
// its weight, zero included) is fixed at construction, so CHOLMOD orders and analyzes it once and
// every later factorization, in every solve, is numeric only. The poses are ordered as blocks
// (fill_reducing_ordering.h: AMD, or METIS on large graphs where it takes fewer flops) and H is
// assembled in that order, so CHOLMOD factors it as stored, without permuting it per
// factorization. Before it does, each step eliminates the poses joined to at most two others
// (chains and leaves, one by one, each joining its neighbours), H_uw -= H_uv D_v^-1 H_vw, and
// substitutes their steps back after: CHOLMOD factors the rest, with far fewer supernodes (a
// supernodal factor numerically by supernodal_cholesky.h, the same factor on up to two threads).

#include <Eigen/Geometry>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace ceres {
class CostFunction;
class Manifold;
}  // namespace ceres

namespace hydra_multi {

class GeodesicFactor;

struct PoseParameters {
  Eigen::Quaterniond q;  ///< Ceres' parameter block order x y z w
  Eigen::Vector3d t;
};

/// A factor r(x_i, x_j): a geodesic one (residuals.h GeodesicFactor, its Jacobian in the tangent
/// space of LeftQuaternionTangentManifold, the solver's rotation manifold then), or else a cost
/// function that takes the blocks q_i, t_i, q_j, t_j and has at most 12 residuals (the constructor
/// throws std::invalid_argument otherwise).
struct LmTerm {
  const ceres::CostFunction* cost = nullptr;
  size_t i = 0, j = 0;
  const GeodesicFactor* geodesic = nullptr;  ///< instead of `cost`
};

struct LmOptions {
  int max_iterations = 100;
  double function_tolerance = 1e-4;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
  /// Threads that linearize and evaluate the cost (from 4,096 terms; fewer: one), and that
  /// factorize a supernodal factor (two at most; supernodal_cholesky.h). Each block of H, segment
  /// of g and term's cost is summed by one thread in term order, and the factor is the one of one
  /// thread: the steps are those of one thread to the bit.
  int threads = 1;
  /// A supernodal factorization of at least this many flops is made in single precision and its
  /// solve refined once in double (supernodal_cholesky.h); negative: always double precision.
  double single_precision_from_flops = -1.0;
};

struct LmSummary {
  bool usable = false;  ///< the poses are finite and no worse than at the start
  std::string message;
  int iterations = 0;  ///< steps tried, taken or not
  double initial_cost = 0.0, final_cost = 0.0;
  double time_s = 0.0;
  double factorization_s = 0.0;  ///< of time_s: the numeric factorizations
  /// Factorizations in single precision (LmOptions::single_precision_from_flops), and those tried
  /// in single precision that failed and were made in double instead.
  int single_precision_factorizations = 0, single_precision_fallbacks = 0;
};

class SparseAnalyses;

class SparseLevenbergMarquardt {
 public:
  /// `fixed`: per pose, held constant (the gauge, and the poses a local solve leaves where they
  /// are); shorter than num_poses: the rest are free. `rotation`: the manifold of every
  /// quaternion block, outliving this. `analyses` (may be null): where an analysis of this
  /// pattern made ahead is taken from instead of analyzing anew, and, with `keep`, where this
  /// one's analysis is left when it ends.
  SparseLevenbergMarquardt(size_t num_poses, std::vector<LmTerm> terms,
                           const std::vector<bool>& fixed, const ceres::Manifold& rotation,
                           SparseAnalyses* analyses = nullptr, bool keep = false);
  ~SparseLevenbergMarquardt();
  SparseLevenbergMarquardt(const SparseLevenbergMarquardt&) = delete;
  SparseLevenbergMarquardt& operator=(const SparseLevenbergMarquardt&) = delete;

  /// Moves `poses` (one per pose) towards the minimum; `weights`: one per term.
  LmSummary solve(std::vector<PoseParameters>& poses, const std::vector<double>& weights,
                  const LmOptions& options);
  /// Floating-point operations of one factorization, as CHOLMOD's analysis counts them (fixed by
  /// the pattern: every term, whatever its weight), the eliminated poses' columns counted alike;
  /// 0 if the analysis failed.
  double factorizationFlops() const;
  size_t freePoses() const;

 private:
  friend class SparseAnalyses;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// An analysis made ahead (on another thread, while an earlier solve runs) for a later problem:
/// its pattern (the number of poses, the terms' poses in order, the fixed poses), its ordering
/// and symbolic factorization. It holds the last analysis left to it; a problem with that
/// pattern takes it (the analysis is a function of the pattern alone, so the solve is the same
/// to the bit), any other leaves it, less its factor's values (heldFactorValues), which go back
/// for that problem's own. Once dropped it holds nothing again. Thread-safe.
class SparseAnalyses {
 public:
  SparseAnalyses();
  ~SparseAnalyses();
  SparseAnalyses(const SparseAnalyses&) = delete;
  SparseAnalyses& operator=(const SparseAnalyses&) = delete;
  /// Whether an analysis is held.
  bool holds() const;
  /// How many numeric values of its factor the held analysis has allocated and written, on the
  /// thread that made it: a supernodal factor's all where its block is kept for reuse
  /// (keptForReuse), until a problem of another pattern frees them; else 0, and the first
  /// factorization makes them.
  size_t heldFactorValues() const;
  /// No problem will take an analysis from here: what is held is freed, and one being made
  /// stops at its next step (before its ordering, before its factor's values) and is not kept.
  void drop();
  bool dropped() const;

 private:
  friend class SparseLevenbergMarquardt;
  void keep(std::unique_ptr<SparseLevenbergMarquardt::Impl> analysis);
  std::unique_ptr<SparseLevenbergMarquardt::Impl> take(size_t num_poses,
                                                       const std::vector<LmTerm>& terms,
                                                       const std::vector<bool>& fixed);
  mutable std::mutex mutex_;
  std::unique_ptr<SparseLevenbergMarquardt::Impl> kept_;
  bool dropped_ = false;
};

}  // namespace hydra_multi
