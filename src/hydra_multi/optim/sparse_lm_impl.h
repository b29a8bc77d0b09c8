#pragma once
// SparseLevenbergMarquardt's state, shared by its three sources: the terms and free poses, H
// stored in the fill-reducing order as CHOLMOD factors it (the eliminated poses' blocks after
// it), the eliminations, and the linearization's partition into threads. Made once per pattern
// (sparse_lm_analysis.cpp), filled each step (sparse_lm_linearization.cpp), then eliminated,
// factorized and solved (sparse_levenberg_marquardt.cpp). Internal to optim.

#include <cholmod.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "hydra_multi/optim/sparse_levenberg_marquardt.h"
#include "hydra_multi/optim/supernodal_cholesky.h"

namespace hydra_multi {
namespace sparse_lm {

using Block = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;
// A term's residual and Jacobians on the stack: at most kMaxResiduals rows (the chordal
// residual's 12; the geodesic one has 6), no allocation per term on the solve's hot path.
constexpr int kMaxResiduals = 12;
using Residual = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxResiduals, 1>;
using JacobianRows = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxResiduals, 6>;
template <int Columns>
using AmbientJacobian =
    Eigen::Matrix<double, Eigen::Dynamic, Columns, Eigen::RowMajor, kMaxResiduals, Columns>;
constexpr long kNone = -1;
constexpr size_t kThreadsFrom = 4096;  // terms: fewer are linearized on one thread

// The Cholesky factor of a symmetric 6x6 block, D = L L^T with L lower triangular (D's lower
// triangle read, L's upper set to zero); false where D is not positive definite (a pivot not above
// zero, or not a number).
bool choleskyFactor(const Block& D, Block& L);
// x <- L^-1 x and x <- L^-T x for a lower triangular L, by substitution.
void solveLower(const Block& L, Vector6& x);
void solveLowerTransposed(const Block& L, Vector6& x);
// B <- B L^-T, column by column: each row of B as solveLower would take it, to the bit.
void solveRightLowerTransposed(const Block& L, Block& B);

// The supernodal symbolic factor of a matrix of dense 6x6 blocks in its natural order, by
// CHOLMOD's analysis of its block pattern (36 times fewer entries): each block supernode's columns
// and rows expanded six-fold, which is the scalar factor's pattern; the relaxed amalgamation's
// column thresholds (`scalar_nrelax`) divided by 6, its shares of zeros counted by blocks.
// `columns`: per block column, its block rows (itself and those below), sorted. Sets `fl` and
// `lnz` to the scalar factor's counts as CHOLMOD's analysis of the scalar matrix would (the sum of
// the squared column counts, and of the counts). Null where CHOLMOD would make the factor
// simplicial (fl below common.supernodal_switch * lnz) or the analysis failed.
cholmod_factor* supernodalFromBlocks(const std::vector<std::vector<long>>& columns,
                                     const size_t scalar_nrelax[3], cholmod_common& common,
                                     double& fl, double& lnz);

}  // namespace sparse_lm

struct SparseLevenbergMarquardt::Impl {
  using Block = sparse_lm::Block;
  using Vector6 = sparse_lm::Vector6;
  using Residual = sparse_lm::Residual;
  using JacobianRows = sparse_lm::JacobianRows;
  static constexpr long kNone = sparse_lm::kNone;

  const ceres::Manifold* rotation = nullptr;
  std::vector<LmTerm> terms;
  std::vector<long> variable;  // pose -> variable block, kNone for fixed poses
  size_t variables = 0;
  // H is stored permuted, A = P H P^T with P the fill-reducing ordering (postordered), lower
  // triangle, so that CHOLMOD factorizes A in its natural order without permuting or transposing
  // it (upper triangle where the factor is simplicial, CHOLMOD's fastest form there). A block of H
  // (block row <= block column) lies in A as six runs of six values (fewer on a diagonal block),
  // one per column of A's block: `column`, per block, each run's index in A's values less its
  // first row; `transposed`, per block, whether A holds it transposed. H's entry (r, c) of the
  // block (a diagonal block's r <= c only) is A's value column[c] + r, or column[r] + c where
  // transposed.
  std::vector<long> column;  // 6 per block
  std::vector<char> transposed;
  std::vector<long> permuted;        // scalar index of H -> that of A (kNone: eliminated)
  std::vector<long> diagonal_block;  // per variable
  // Variables eliminated before CHOLMOD factorizes the rest (A): one by one, each joined to at
  // most two others then. Per elimination: the variable, those neighbours (kNone where fewer),
  // its blocks to them, their diagonal blocks and the block between them (the fill). The blocks
  // of an eliminated variable are stored after A's values (36 per block, column-major, not
  // transposed). The eliminations change H's values: each step starts from H linearized afresh
  // (a step not taken linearizes again at the same poses, to the same values).
  // On two threads the eliminations before `elimination_split` run on one, the rest on the
  // other (0: all on one). No chain or tree of eliminated variables spans the split, so neither
  // thread reads what the other writes. Both write only blocks of variables in A: the second
  // thread's writes to those the first also writes (`deferred`, bit n: u_n's diagonal block and
  // rhs segment; bit 2: u01) are applied after both, in order, as one thread would add them.
  struct Elimination {
    long v = kNone;
    std::array<long, 2> u{kNone, kNone}, vu{kNone, kNone}, uu{kNone, kNone};
    long u01 = kNone;
    uint8_t deferred = 0;
  };
  std::vector<Elimination> eliminations;
  size_t elimination_split = 0;
  struct DeferredBlock {
    long block;
    bool diagonal;
    Block value;
  };
  struct DeferredRhs {
    long variable;
    Vector6 value;
  };
  std::vector<DeferredBlock> deferred_blocks;  // room for them all reserved by the analysis
  std::vector<DeferredRhs> deferred_rhs;
  size_t reduced = 0;  // variables in A
  // Per elimination, for the substitution: the Cholesky factor of D_v = L_v L_v^T, L_v^-1 rhs_v,
  // and H_uv L_v^-T per neighbour u.
  std::vector<Block> factors;
  std::vector<Vector6> solved_rhs;
  std::vector<std::array<Block, 2>> neighbour_products;
  // Per term: its blocks (i, i), (j, j) and (min, max) of H; kNone where a pose is fixed.
  struct TermBlocks {
    long ii = kNone, jj = kNone, ij = kNone;
  };
  std::vector<TermBlocks> term_blocks;
  // Per thread of the linearization, the terms it visits in order, each with what
  // it adds: the blocks (i, i), (j, j), (min, max) of H and g's segments of the variables the
  // thread owns (a contiguous range), and the term's cost if the term's first free pose is one
  // of them (thread 0 for a term between fixed poses).
  enum Part : uint8_t { kOwnI = 1, kOwnJ = 2, kOwnIJ = 4, kOwnCost = 8 };
  struct Visit {
    uint32_t term;
    uint8_t parts;
  };
  std::vector<std::vector<Visit>> visits;
  mutable std::vector<double> term_cost;  // per term, its 1/2 w ||r||^2
  cholmod_common common;
  cholmod_sparse* H = nullptr;
  cholmod_factor* L = nullptr;
  // A supernodal L's numeric factorization and its solves, ours in place of CHOLMOD's (the
  // same factor and solutions, to the bit).
  std::unique_ptr<SupernodalCholesky> supernodal;
  double flops = 0.0;  // of one factorization, from the analysis
  // Where the analysis goes when the solver ends; the terms then keep only their poses, which
  // the pattern is (their costs end with their problem).
  SparseAnalyses* keep_in = nullptr;

  ~Impl() {
    if (L != nullptr) cholmod_l_free_factor(&L, &common);
    if (H != nullptr) cholmod_l_free_sparse(&H, &common);
    cholmod_l_finish(&common);
  }

  // Adds m to block `block` of H (a diagonal block: its upper triangle), run by run of A.
  void add(long block, const Block& m, bool diagonal) {
    if (block == kNone) return;
    double* x = static_cast<double*>(H->x);
    const long* at = &column[6 * block];
    if (transposed[block]) {
      for (int r = 0; r < 6; ++r) {
        double* run = x + at[r];
        for (int c = diagonal ? r : 0; c < 6; ++c) run[c] += m(r, c);
      }
    } else {
      for (int c = 0; c < 6; ++c) {
        double* run = x + at[c];
        const int rows = diagonal ? c + 1 : 6;
        for (int r = 0; r < rows; ++r) run[r] += m(r, c);
      }
    }
  }
  // Where H's entry (r, c) of block `block` is in A's values.
  long slot(long block, int r, int c) const {
    const long* at = &column[6 * block];
    return transposed[block] ? at[r] + c : at[c] + r;
  }
  // Where H's diagonal entry (c, c) of variable v is in A's values.
  long diagonalSlot(size_t v, int c) const { return slot(diagonal_block[v], c, c); }

  // Block `block` of H as stored: H_rc for its pair (r, c), a diagonal block made symmetric.
  Block read(long block, bool diagonal) const {
    const double* x = static_cast<const double*>(H->x);
    const long* at = &column[6 * block];
    Block m;
    if (transposed[block]) {
      for (int r = 0; r < 6; ++r) {
        const double* run = x + at[r];
        for (int c = diagonal ? r : 0; c < 6; ++c) m(r, c) = run[c];
      }
    } else {
      for (int c = 0; c < 6; ++c) {
        const double* run = x + at[c];
        const int rows = diagonal ? c + 1 : 6;
        for (int r = 0; r < rows; ++r) m(r, c) = run[r];
      }
    }
    for (int c = 0; c < 6 && diagonal; ++c) {
      for (int r = c + 1; r < 6; ++r) m(r, c) = m(c, r);
    }
    return m;
  }
  // H_uv of elimination e's neighbour k and its variable.
  Block toNeighbour(const Elimination& e, int k) const {
    const Block stored = read(e.vu[k], false);
    return e.u[k] < e.v ? stored : Block(stored.transpose());
  }

  // The pattern of H for the terms with `fixed` poses held: the variables, the eliminations of
  // chains and leaves, A's blocks in a fill-reducing order, CHOLMOD's symbolic factorization (L
  // null where any of it failed; solve() reports it). Once, at construction.
  void analyze(size_t num_poses, const std::vector<bool>& fixed);
  // L's numeric values allocated and written once, so that their pages are faulted in on the
  // calling thread: an analysis made ahead does it before it is kept, and the solve's first
  // factorization then only fills L. Only a supernodal L whose block the SuiteSparse keeper keeps
  // for reuse (keptForReuse); nothing where the analysis failed or L has its values.
  void allocateFactor();
  // L's numeric values freed, its symbolic factorization kept (a supernodal L that has them).
  void freeFactorValues();
  // A supernodal L's numeric values allocated where it has none (not written); false where
  // CHOLMOD could not.
  bool allocateValues();
  // L <- the factor of A (H as eliminated and damped): a supernodal L by `supernodal` on
  // `threads` threads, its values allocated first where it has none, in single precision where
  // it takes at least `single_from_flops` (>= 0) and that succeeds; a simplicial L by CHOLMOD.
  // False where A is not positive definite.
  bool factorize(int threads, double single_from_flops, LmSummary& summary);

  // Where the eliminations split for two threads (elimination_split, Elimination::deferred), from
  // `blocks`, the number of H's blocks. Once, by the analysis.
  void splitEliminations(size_t blocks);
  // The eliminations on the damped H and the right-hand side `rhs` (-g, per variable), in order:
  // H_uw -= H_uv D_v^-1 H_vw and rhs_u -= H_uv D_v^-1 rhs_v for the neighbours u, w of v, through
  // D_v = L_v L_v^T: H_uv D_v^-1 H_vw = Y_u Y_w^T with Y_u = H_uv L_v^-T. On two threads where
  // `threads` allows and they split; the same values to the bit. False where a D_v is not positive
  // definite.
  bool eliminate(Eigen::VectorXd& rhs, int threads);
  // Eliminations [first, last) in order; with `defer`, the writes their `deferred` bits name are
  // left in deferred_blocks and deferred_rhs.
  bool eliminateRange(size_t first, size_t last, Eigen::VectorXd& rhs, bool defer);
  // The eliminated variables' steps from the others', last elimination first:
  // delta_v = D_v^-1 rhs_v - sum_u (H_uv D_v^-1)^T delta_u = L_v^-T (L_v^-1 rhs_v - sum_u Y_u^T
  // delta_u). Each side of the split on its own thread where `threads` allows.
  void substituteBack(Eigen::VectorXd& step, int threads);

  // The residual of term k at `poses` and, if `J_i`/`J_j` are given, its tangent Jacobians.
  bool evaluate(size_t k, const std::vector<PoseParameters>& poses, Residual& r, JacobianRows* J_i,
                JacobianRows* J_j) const;
  size_t threadsFor(int requested) const;
  // 1/2 sum_k w_k ||r_k||^2, summed in term order from per-term values whatever the threads;
  // infinity if a residual cannot be evaluated or is not finite.
  double cost(const std::vector<PoseParameters>& poses, const std::vector<double>& weights,
              int requested_threads) const;
  // The sum of term_cost in term order; infinity if a thread failed or it is not finite.
  double summedCost(const std::vector<char>& failed) const;
  // Which thread adds what (visits), for `threads` threads: each owns a contiguous range of
  // variables holding about 1/threads of the terms' ends.
  void partition(size_t threads);
  // Adds a term's parts (Part) to H, g and term_cost from its residual r and tangent Jacobians:
  // fixed 6-row matrices for a geodesic term, up to kMaxResiduals rows else.
  template <typename ResidualType, typename JacobianType>
  void addTerm(size_t k, uint8_t parts, double w, Eigen::VectorXd& g, const ResidualType& r,
               const JacobianType& J_i, const JacobianType& J_j);
  // Adds term k's parts (Part) at `poses` to H, g and term_cost; false if it cannot be evaluated.
  bool linearizeTerm(size_t k, uint8_t parts, const std::vector<PoseParameters>& poses, double w,
                     Eigen::VectorXd& g, Residual& r, JacobianRows& J_i, JacobianRows& J_j);
  // H = J^T W J into the CHOLMOD values, g = J^T W r; returns the cost (infinity on failure). Each
  // H block, g segment and term's cost is summed by one thread in term order, so the result is
  // the same to the bit whatever the threads.
  double linearize(const std::vector<PoseParameters>& poses, const std::vector<double>& weights,
                   Eigen::VectorXd& g, int requested_threads);
};

}  // namespace hydra_multi
