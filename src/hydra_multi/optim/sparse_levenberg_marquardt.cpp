#include "hydra_multi/optim/sparse_levenberg_marquardt.h"

#include <ceres/ceres.h>
#include <cholmod.h>
#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "hydra_multi/core/parallel.h"
#include "hydra_multi/optim/fill_reducing_ordering.h"
#include "hydra_multi/optim/residuals.h"
#include "hydra_multi/optim/serial_openmp.h"
#include "hydra_multi/optim/suitesparse_blocks.h"

namespace hydra_multi {
namespace {

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

// Ceres' Levenberg-Marquardt constants (Solver::Options defaults).
constexpr double kInitialRadius = 1e4;
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinDiagonal = 1e-6;
constexpr double kMaxDiagonal = 1e32;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr int kMaxConsecutiveInvalidSteps = 5;
constexpr size_t kBothOrderingsFrom = 5000;  // variables
constexpr size_t kThreadsFrom = 4096;        // terms: fewer are linearized on one thread

// The order in which to eliminate variables of a graph (`neighbours`: per variable, the others a
// term joins it to): one by one, any joined to at most two others (a pose of a chain, a leaf), its
// neighbours then joined to each other; at least one variable is left. Per elimination, the
// variable and its neighbours then (kNone where fewer).
std::vector<std::pair<long, std::array<long, 2>>> chainsAndLeaves(
    std::vector<std::vector<long>> neighbours) {
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  const auto unlink = [&](long from, long v) {
    auto& list = neighbours[from];
    list.erase(std::lower_bound(list.begin(), list.end(), v));
  };
  const auto link = [&](long a, long b) {
    auto& list = neighbours[a];
    const auto at = std::lower_bound(list.begin(), list.end(), b);
    if (at == list.end() || *at != b) list.insert(at, b);
  };
  std::vector<std::pair<long, std::array<long, 2>>> order;
  std::vector<char> eliminated(neighbours.size(), 0);
  std::vector<long> candidates;
  for (size_t v = neighbours.size(); v-- > 0;) {
    if (neighbours[v].size() <= 2) candidates.push_back(static_cast<long>(v));
  }
  size_t kept = neighbours.size();
  while (!candidates.empty() && kept > 1) {
    const long v = candidates.back();
    candidates.pop_back();
    if (eliminated[v] || neighbours[v].size() > 2) continue;
    std::array<long, 2> u{kNone, kNone};
    for (size_t k = 0; k < neighbours[v].size(); ++k) u[k] = neighbours[v][k];
    for (const long w : neighbours[v]) unlink(w, v);
    if (u[1] != kNone) {
      link(u[0], u[1]);
      link(u[1], u[0]);
    }
    neighbours[v].clear();
    eliminated[v] = 1;
    --kept;
    order.emplace_back(v, u);
    for (const long w : u) {
      if (w != kNone && neighbours[w].size() <= 2) candidates.push_back(w);
    }
  }
  return order;
}

}  // namespace

struct SparseLevenbergMarquardt::Impl {
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
  struct Elimination {
    long v = kNone;
    std::array<long, 2> u{kNone, kNone}, vu{kNone, kNone}, uu{kNone, kNone};
    long u01 = kNone;
  };
  std::vector<Elimination> eliminations;
  size_t reduced = 0;  // variables in A
  // Per elimination, for the substitution: D_v^-1 rhs_v and H_uv D_v^-1 per neighbour u.
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
  double flops = 0.0;  // of one factorization, from the analysis
  // Where the analysis goes when the solver ends; the terms then keep only their poses, which
  // the pattern is (their costs end with their problem).
  SparseAnalyses* keep_in = nullptr;

  ~Impl() {
    if (L != nullptr) cholmod_l_free_factor(&L, &common);
    if (H != nullptr) cholmod_l_free_sparse(&H, &common);
    cholmod_l_finish(&common);
  }

  // Adds m to block `block` of H (a diagonal block: its upper triangle).
  void add(long block, const Block& m, bool diagonal) {
    if (block == kNone) return;
    double* x = static_cast<double*>(H->x);
    const long* at = &column[6 * block];
    if (transposed[block]) {
      for (int c = 0; c < 6; ++c) {
        const int rows = diagonal ? c + 1 : 6;
        for (int r = 0; r < rows; ++r) x[at[r] + c] += m(r, c);
      }
    } else {
      for (int c = 0; c < 6; ++c) {
        const int rows = diagonal ? c + 1 : 6;
        for (int r = 0; r < rows; ++r) x[at[c] + r] += m(r, c);
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
    Block m;
    for (int c = 0; c < 6; ++c) {
      for (int r = 0; r < 6; ++r) {
        if (diagonal && r > c) continue;
        m(r, c) = x[slot(block, r, c)];
        if (diagonal) m(c, r) = m(r, c);
      }
    }
    return m;
  }
  // H_uv of elimination e's neighbour k and its variable.
  Block toNeighbour(const Elimination& e, int k) const {
    const Block stored = read(e.vu[k], false);
    return e.u[k] < e.v ? stored : Block(stored.transpose());
  }

  // The eliminations on the damped H and the right-hand side `rhs` (-g, per variable), in order:
  // H_uw -= H_uv D_v^-1 H_vw and rhs_u -= H_uv D_v^-1 rhs_v for the neighbours u, w of v. False
  // where a D_v is not positive definite.
  bool eliminate(Eigen::VectorXd& rhs) {
    solved_rhs.resize(eliminations.size());
    neighbour_products.resize(eliminations.size());
    for (size_t k = 0; k < eliminations.size(); ++k) {
      const Elimination& e = eliminations[k];
      const Eigen::LLT<Block> llt(read(diagonal_block[e.v], true));
      if (llt.info() != Eigen::Success) return false;
      const Block inverse = llt.solve(Block::Identity());
      const Vector6 r = rhs.segment<6>(6 * e.v);
      solved_rhs[k] = inverse * r;
      std::array<Block, 2> B;
      std::array<Block, 2>& X = neighbour_products[k];
      for (int n = 0; n < 2 && e.u[n] != kNone; ++n) {
        B[n] = toNeighbour(e, n);
        X[n] = B[n] * inverse;
        add(e.uu[n], -(X[n] * B[n].transpose()), true);
        rhs.segment<6>(6 * e.u[n]) -= X[n] * r;
      }
      if (e.u01 != kNone) {
        const Block S = X[0] * B[1].transpose();  // the update of H_{u0 u1}
        add(e.u01, e.u[0] < e.u[1] ? Block(-S) : Block(-S.transpose()), false);
      }
    }
    return true;
  }
  // The eliminated variables' steps from the others', last elimination first:
  // delta_v = D_v^-1 rhs_v - sum_u (H_uv D_v^-1)^T delta_u.
  void substituteBack(Eigen::VectorXd& step) {
    for (size_t k = eliminations.size(); k-- > 0;) {
      const Elimination& e = eliminations[k];
      Vector6 delta = solved_rhs[k];
      for (int n = 0; n < 2 && e.u[n] != kNone; ++n)
        delta -= neighbour_products[k][n].transpose() * step.segment<6>(6 * e.u[n]);
      step.segment<6>(6 * e.v) = delta;
    }
  }

  // The residual of term k at `poses` and, if `J_i`/`J_j` are given, its tangent Jacobians.
  bool evaluate(size_t k, const std::vector<PoseParameters>& poses, Residual& r, JacobianRows* J_i,
                JacobianRows* J_j) const {
    const LmTerm& term = terms[k];
    const PoseParameters& a = poses[term.i];
    const PoseParameters& b = poses[term.j];
    const bool free_i = variable[term.i] != kNone, free_j = variable[term.j] != kNone;
    if (term.geodesic != nullptr) {
      Vector6 r6;
      Block J6_i, J6_j;
      const bool jacobians = J_i != nullptr;
      term.geodesic->evaluate(a.q, a.t, b.q, b.t, r6, jacobians && free_i ? &J6_i : nullptr,
                              jacobians && free_j ? &J6_j : nullptr);
      r = r6;
      if (jacobians && free_i) *J_i = J6_i;
      if (jacobians && free_j) *J_j = J6_j;
      return true;
    }
    const double* parameters[4] = {a.q.coeffs().data(), a.t.data(), b.q.coeffs().data(),
                                   b.t.data()};
    const int m = term.cost->num_residuals();
    r.resize(m);
    if (J_i == nullptr) return term.cost->Evaluate(parameters, r.data(), nullptr);
    AmbientJacobian<4> q_i(m, 4), q_j(m, 4);
    AmbientJacobian<3> t_i(m, 3), t_j(m, 3);
    double* jacobians[4] = {free_i ? q_i.data() : nullptr, free_i ? t_i.data() : nullptr,
                            free_j ? q_j.data() : nullptr, free_j ? t_j.data() : nullptr};
    if (!term.cost->Evaluate(parameters, r.data(), jacobians)) return false;
    Eigen::Matrix<double, 4, 3, Eigen::RowMajor> plus;
    if (free_i) {
      rotation->PlusJacobian(a.q.coeffs().data(), plus.data());
      J_i->resize(m, 6);
      J_i->leftCols<3>() = q_i * plus;
      J_i->rightCols<3>() = t_i;
    }
    if (free_j) {
      rotation->PlusJacobian(b.q.coeffs().data(), plus.data());
      J_j->resize(m, 6);
      J_j->leftCols<3>() = q_j * plus;
      J_j->rightCols<3>() = t_j;
    }
    return true;
  }

  size_t threadsFor(int requested) const {
    if (requested <= 1 || terms.size() < kThreadsFrom) return 1;
    return std::min<size_t>(static_cast<size_t>(requested), 8);
  }

  // 1/2 sum_k w_k ||r_k||^2, summed in term order from per-term values whatever the threads;
  // infinity if a residual cannot be evaluated or is not finite.
  double cost(const std::vector<PoseParameters>& poses, const std::vector<double>& weights,
              int requested_threads) const {
    const size_t threads = threadsFor(requested_threads);
    term_cost.assign(terms.size(), 0.0);
    std::vector<char> failed(threads, 0);
    runOnThreads(threads, [&](size_t t) {
      Residual r;
      const size_t first = terms.size() * t / threads, last = terms.size() * (t + 1) / threads;
      for (size_t k = first; k < last; ++k) {
        const double w = k < weights.size() ? weights[k] : 1.0;
        if (w == 0.0) continue;
        if (!evaluate(k, poses, r, nullptr, nullptr)) {
          failed[t] = 1;
          return;
        }
        term_cost[k] = 0.5 * w * r.squaredNorm();
      }
    });
    return summedCost(failed);
  }

  // The sum of term_cost in term order; infinity if a thread failed or it is not finite.
  double summedCost(const std::vector<char>& failed) const {
    if (std::find(failed.begin(), failed.end(), 1) != failed.end()) return HUGE_VAL;
    double total = 0.0;
    for (const double c : term_cost) total += c;
    return std::isfinite(total) ? total : HUGE_VAL;
  }

  // Which thread adds what (visits), for `threads` threads: each owns a contiguous range of
  // variables holding about 1/threads of the terms' ends.
  void partition(size_t threads) {
    if (visits.size() == threads) return;
    std::vector<size_t> ends(variables, 0);
    size_t total = 0;
    for (const LmTerm& t : terms) {
      for (const size_t pose : {t.i, t.j}) {
        if (variable[pose] == kNone) continue;
        ++ends[static_cast<size_t>(variable[pose])];
        ++total;
      }
    }
    std::vector<size_t> owner(variables);
    size_t seen = 0;
    for (size_t v = 0; v < variables; ++v) {
      owner[v] = std::min(threads - 1, seen * threads / std::max<size_t>(total, 1));
      seen += ends[v];
    }
    visits.assign(threads, {});
    for (size_t k = 0; k < terms.size(); ++k) {
      const long vi = variable[terms[k].i], vj = variable[terms[k].j];
      const size_t cost_owner = vi != kNone ? owner[vi] : vj != kNone ? owner[vj] : 0;
      for (size_t t = 0; t < threads; ++t) {
        uint8_t parts = t == cost_owner ? kOwnCost : 0;
        if (vi != kNone && owner[vi] == t) parts |= kOwnI;
        if (vj != kNone && owner[vj] == t) parts |= kOwnJ;
        if (vi != kNone && vj != kNone && vi != vj && owner[std::max(vi, vj)] == t) parts |= kOwnIJ;
        if (parts != 0) visits[t].push_back({static_cast<uint32_t>(k), parts});
      }
    }
  }

  // Adds term k's parts (Part) at `poses` to H, g and term_cost; false if it cannot be evaluated.
  bool linearizeTerm(size_t k, uint8_t parts, const std::vector<PoseParameters>& poses, double w,
                     Eigen::VectorXd& g, Residual& r, JacobianRows& J_i, JacobianRows& J_j) {
    if (!evaluate(k, poses, r, &J_i, &J_j)) return false;
    if (parts & kOwnCost) term_cost[k] = 0.5 * w * r.squaredNorm();
    const long vi = variable[terms[k].i], vj = variable[terms[k].j];
    const TermBlocks& b = term_blocks[k];
    if (parts & kOwnI) {
      add(b.ii, w * J_i.transpose() * J_i, true);
      g.segment<6>(6 * vi) += w * J_i.transpose() * r;
    }
    if (parts & kOwnJ) {
      add(b.jj, w * J_j.transpose() * J_j, true);
      g.segment<6>(6 * vj) += w * J_j.transpose() * r;
    }
    if (parts & kOwnIJ) {
      const Block m = vi < vj ? Block(w * J_i.transpose() * J_j) : Block(w * J_j.transpose() * J_i);
      add(b.ij, m, false);
    }
    return true;
  }

  // H = J^T W J into the CHOLMOD values, g = J^T W r; returns the cost (infinity on failure). Each
  // H block, g segment and term's cost is summed by one thread in term order, so the result is
  // the same to the bit whatever the threads.
  double linearize(const std::vector<PoseParameters>& poses, const std::vector<double>& weights,
                   Eigen::VectorXd& g, int requested_threads) {
    std::fill_n(static_cast<double*>(H->x), H->nzmax, 0.0);
    g.setZero(static_cast<Eigen::Index>(6 * variables));
    const size_t threads = threadsFor(requested_threads);
    partition(threads);
    term_cost.assign(terms.size(), 0.0);
    std::vector<char> failed(threads, 0);
    runOnThreads(threads, [&](size_t t) {
      Residual r;
      JacobianRows J_i, J_j;
      for (const Visit& visit : visits[t]) {
        const double w = visit.term < weights.size() ? weights[visit.term] : 1.0;
        if (w == 0.0) continue;
        if (!linearizeTerm(visit.term, visit.parts, poses, w, g, r, J_i, J_j)) {
          failed[t] = 1;
          return;
        }
      }
    });
    return summedCost(failed);
  }
};

SparseLevenbergMarquardt::SparseLevenbergMarquardt(size_t num_poses, std::vector<LmTerm> terms,
                                                   const std::vector<bool>& fixed,
                                                   const ceres::Manifold& rotation,
                                                   SparseAnalyses* analyses, bool keep) {
  for (const LmTerm& t : terms) {
    if (t.geodesic == nullptr && t.cost->num_residuals() > kMaxResiduals)
      throw std::invalid_argument("SparseLevenbergMarquardt: a term has more than " +
                                  std::to_string(kMaxResiduals) + " residuals");
  }
  if (analyses != nullptr) impl_ = analyses->take(num_poses, terms, fixed);
  const bool ahead = impl_ != nullptr;
  if (!ahead) impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.rotation = &rotation;
  m.terms = std::move(terms);
  m.keep_in = keep ? analyses : nullptr;
  if (ahead) return;
  keepSuiteSparseBlocks();  // the factor of the last problem, reused without page faults
  cholmod_l_start(&m.common);
  m.common.print = 0;
  m.common.error_handler = nullptr;
  m.variable.assign(num_poses, kNone);
  for (size_t p = 0; p < num_poses; ++p) {
    if (p >= fixed.size() || !fixed[p]) m.variable[p] = static_cast<long>(m.variables++);
  }
  // The variables eliminated before CHOLMOD, and the fill between their neighbours.
  std::vector<std::vector<long>> neighbours(m.variables);
  for (const LmTerm& t : m.terms) {
    const long a = m.variable[t.i], b = m.variable[t.j];
    if (a == kNone || b == kNone || a == b) continue;
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  std::vector<char> eliminated(m.variables, 0);
  std::vector<std::pair<long, long>> fill;
  for (const auto& [v, u] : chainsAndLeaves(std::move(neighbours))) {
    Impl::Elimination e;
    e.v = v;
    e.u = u;
    eliminated[v] = 1;
    if (u[1] != kNone) fill.emplace_back(u[0], u[1]);
    m.eliminations.push_back(e);
  }
  // The blocks of H: per variable column, its rows (itself, the variables a term joins it to
  // from above, and the fill).
  std::vector<std::vector<long>> rows(m.variables);
  for (size_t v = 0; v < m.variables; ++v) rows[v].push_back(static_cast<long>(v));
  for (const LmTerm& t : m.terms) {
    const long a = m.variable[t.i], b = m.variable[t.j];
    if (a == kNone || b == kNone || a == b) continue;
    rows[std::max(a, b)].push_back(std::min(a, b));
  }
  for (const auto& [a, b] : fill) rows[std::max(a, b)].push_back(std::min(a, b));
  for (auto& list : rows) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  // Block ids, column by column; per block its (row, column) variables.
  std::vector<std::vector<long>> block_of(m.variables);  // per column, per row in `rows`
  std::vector<std::pair<long, long>> block_at;
  for (size_t c = 0; c < m.variables; ++c) {
    for (const long r : rows[c]) {
      block_of[c].push_back(static_cast<long>(block_at.size()));
      block_at.emplace_back(r, static_cast<long>(c));
    }
  }
  m.diagonal_block.resize(m.variables);
  for (size_t c = 0; c < m.variables; ++c) m.diagonal_block[c] = block_of[c].back();
  const auto blockOf = [&](long r, long c) {
    if (r > c) std::swap(r, c);
    const auto& list = rows[c];
    const size_t k = std::lower_bound(list.begin(), list.end(), r) - list.begin();
    return block_of[c][k];
  };
  m.term_blocks.resize(m.terms.size());
  for (size_t k = 0; k < m.terms.size(); ++k) {
    const long a = m.variable[m.terms[k].i], b = m.variable[m.terms[k].j];
    Impl::TermBlocks& tb = m.term_blocks[k];
    if (a != kNone) tb.ii = m.diagonal_block[a];
    if (b != kNone) tb.jj = m.diagonal_block[b];
    if (a != kNone && b != kNone && a != b) tb.ij = blockOf(a, b);
  }
  double elimination_flops = 0.0;  // CHOLMOD's count for their columns: sum of squared counts
  for (Impl::Elimination& e : m.eliminations) {
    const int degree = (e.u[0] != kNone) + (e.u[1] != kNone);
    for (int c = 0; c < 6; ++c) elimination_flops += std::pow(6.0 - c + 6.0 * degree, 2);
    for (int n = 0; n < degree; ++n) {
      e.vu[n] = blockOf(e.v, e.u[n]);
      e.uu[n] = m.diagonal_block[e.u[n]];
    }
    if (degree == 2) e.u01 = blockOf(e.u[0], e.u[1]);
  }
  // A: the variables not eliminated, with their blocks.
  std::vector<long> reduced(m.variables, kNone);
  for (size_t v = 0; v < m.variables; ++v) {
    if (!eliminated[v]) reduced[v] = static_cast<long>(m.reduced++);
  }
  const auto inA = [&](size_t k) {
    return !eliminated[block_at[k].first] && !eliminated[block_at[k].second];
  };
  std::vector<std::vector<long>> reduced_rows(m.reduced);
  size_t nonzeros = 0, tail_blocks = 0;
  for (size_t k = 0; k < block_at.size(); ++k) {
    if (!inA(k)) {
      ++tail_blocks;
      continue;
    }
    const long r = reduced[block_at[k].first], c = reduced[block_at[k].second];
    reduced_rows[c].push_back(r);
    nonzeros += r == c ? 21 : 36;
  }
  const size_t n = 6 * m.reduced;
  // A's block columns in the triangle `stype` (-1 lower, +1 upper), variables placed at
  // `position`: per column, its blocks (row, H's block) sorted by row.
  const auto placeBlocks = [&](const std::vector<long>& position, int stype) {
    std::vector<std::vector<std::pair<long, long>>> columns(m.reduced);
    for (size_t k = 0; k < block_at.size(); ++k) {
      if (!inA(k)) continue;
      const long pr = position[block_at[k].first], pc = position[block_at[k].second];
      const long low = std::min(pr, pc), high = std::max(pr, pc);
      if (stype < 0) {
        columns[low].emplace_back(high, static_cast<long>(k));
      } else {
        columns[high].emplace_back(low, static_cast<long>(k));
      }
    }
    for (auto& column : columns) std::sort(column.begin(), column.end());
    return columns;
  };
  // A as a CHOLMOD matrix (values zero; only the pattern for `values` false) and, with `values`,
  // `column` and `transposed`, the eliminated blocks' values after A's. An entry (i, j) of A's
  // block at (R, C) is H's entry (i, j) of its block where R is that block's row variable and R !=
  // C, else (j, i); a diagonal block keeps one triangle.
  const auto store = [&](const std::vector<long>& position, int stype, bool values) {
    const auto columns = placeBlocks(position, stype);
    cholmod_sparse* A = cholmod_l_allocate_sparse(
        n, n, nonzeros + (values ? 36 * tail_blocks : 0), /*sorted=*/1, /*packed=*/1, stype,
        values ? CHOLMOD_REAL : CHOLMOD_PATTERN, &m.common);
    if (A == nullptr) return A;
    auto* column_start = static_cast<SuiteSparse_long*>(A->p);
    auto* row_index = static_cast<SuiteSparse_long*>(A->i);
    if (values) {
      m.column.assign(6 * block_at.size(), kNone);
      m.transposed.assign(block_at.size(), 0);
    }
    long at = 0;
    for (size_t C = 0; C < m.reduced; ++C) {
      for (int j = 0; j < 6; ++j) {
        column_start[6 * C + j] = at;
        for (const auto& [R, k] : columns[C]) {
          const bool diagonal = R == static_cast<long>(C);
          const bool as_stored = !diagonal && position[block_at[k].first] == R;
          const int first = diagonal && stype < 0 ? j : 0;
          const int last = diagonal && stype > 0 ? j : 5;
          if (values) {
            m.column[6 * k + j] = at - first;
            m.transposed[k] = !as_stored && !(diagonal && stype > 0);
          }
          for (int i = first; i <= last; ++i) row_index[at++] = 6 * R + i;
        }
      }
    }
    column_start[n] = at;
    if (values) {
      for (size_t k = 0; k < block_at.size(); ++k) {
        if (inA(k)) continue;
        for (int c = 0; c < 6; ++c) m.column[6 * k + c] = at + 6 * c;
        at += 36;
      }
      std::fill_n(static_cast<double*>(A->x), at, 0.0);
    }
    return A;
  };
  // Fill-reducing ordering of A's variables, once.
  for (auto& list : reduced_rows) std::sort(list.begin(), list.end());
  const std::optional<FillReducingOrdering> ordering =
      orderForCholesky(reduced_rows, kBothOrderingsFrom);
  if (!ordering) return;                           // solve() reports it
  std::vector<long> position(m.variables, kNone);  // variable -> its place in A
  for (size_t v = 0; v < m.variables; ++v) {
    if (reduced[v] != kNone) position[v] = reduced[v];
  }
  std::vector<long> place(m.reduced);
  for (size_t k = 0; k < m.reduced; ++k) place[ordering->column[k]] = static_cast<long>(k);
  for (long& p : position) {
    if (p != kNone) p = place[p];
  }
  m.permuted.assign(6 * m.variables, kNone);
  for (size_t v = 0; v < m.variables; ++v) {
    for (int c = 0; c < 6 && position[v] != kNone; ++c) m.permuted[6 * v + c] = 6 * position[v] + c;
  }
  // The symbolic factorization of A in its natural order, which the ordering already postordered;
  // small supernodes merged more than by default.
  m.common.nrelax[0] = 8;
  m.common.nrelax[1] = 32;
  m.common.nrelax[2] = 256;
  m.common.zrelax[0] = 0.8;
  m.common.zrelax[1] = 0.2;
  m.common.zrelax[2] = 0.1;
  m.H = store(position, -1, true);
  if (m.H == nullptr) return;
  m.common.supernodal = CHOLMOD_AUTO;
  m.common.final_asis = 1;  // the factor as computed: no conversion after each factorization
  m.common.postorder = 0;
  m.common.nmethods = 1;
  m.common.method[0].ordering = CHOLMOD_NATURAL;
  m.L = cholmod_l_analyze(m.H, &m.common);
  if (m.L != nullptr) m.flops = m.common.fl + elimination_flops;
  if (m.L != nullptr && !m.L->is_super) {
    cholmod_l_free_sparse(&m.H, &m.common);
    m.H = store(position, 1, true);
  }
}

SparseLevenbergMarquardt::~SparseLevenbergMarquardt() {
  SparseAnalyses* keep_in = impl_->keep_in;
  if (keep_in != nullptr && impl_->L != nullptr && impl_->H != nullptr) {
    impl_->keep_in = nullptr;
    keep_in->keep(std::move(impl_));
  }
}

double SparseLevenbergMarquardt::factorizationFlops() const { return impl_->flops; }
size_t SparseLevenbergMarquardt::freePoses() const { return impl_->variables; }

SparseAnalyses::SparseAnalyses() = default;
SparseAnalyses::~SparseAnalyses() = default;

bool SparseAnalyses::holds() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return kept_ != nullptr;
}

void SparseAnalyses::keep(std::unique_ptr<SparseLevenbergMarquardt::Impl> analysis) {
  const std::lock_guard<std::mutex> lock(mutex_);
  kept_ = std::move(analysis);
}

std::unique_ptr<SparseLevenbergMarquardt::Impl> SparseAnalyses::take(
    size_t num_poses, const std::vector<LmTerm>& terms, const std::vector<bool>& fixed) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (kept_ == nullptr || kept_->variable.size() != num_poses ||
      kept_->terms.size() != terms.size())
    return nullptr;
  for (size_t p = 0; p < num_poses; ++p) {
    const bool held = p < fixed.size() && fixed[p];
    if (held != (kept_->variable[p] == kNone)) return nullptr;
  }
  for (size_t k = 0; k < terms.size(); ++k) {
    if (kept_->terms[k].i != terms[k].i || kept_->terms[k].j != terms[k].j) return nullptr;
  }
  return std::move(kept_);
}

LmSummary SparseLevenbergMarquardt::solve(std::vector<PoseParameters>& poses,
                                          const std::vector<double>& weights,
                                          const LmOptions& options) {
  Impl& m = *impl_;
  const SerialOpenMp serial;  // CHOLMOD's per-supernode loops, on this thread
  const auto start = std::chrono::steady_clock::now();
  LmSummary summary;
  const auto finish = [&](const std::string& why) {
    summary.message = "Levenberg-Marquardt (CHOLMOD): " + why + ", " +
                      std::to_string(summary.iterations) + " iterations";
    summary.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  };
  if (m.L == nullptr || m.H == nullptr) return finish("the symbolic factorization failed");
  const size_t n = 6 * m.variables;
  Eigen::VectorXd g;
  // Without iterations (a problem prepared for its analysis), the cost alone.
  double cost = options.max_iterations > 0 ? m.linearize(poses, weights, g, options.threads)
                                           : m.cost(poses, weights, options.threads);
  summary.initial_cost = summary.final_cost = cost;
  if (!std::isfinite(cost)) return finish("the initial cost is not finite");
  summary.usable = true;
  if (m.variables == 0) return finish("no free poses");

  double radius = kInitialRadius, decrease_factor = 2.0;
  int invalid_steps = 0;
  bool linearized = true;
  std::vector<double> diagonal(n);
  Eigen::VectorXd step(static_cast<Eigen::Index>(n));
  cholmod_dense* b = cholmod_l_zeros(6 * m.reduced, 1, CHOLMOD_REAL, &m.common);
  Eigen::VectorXd rhs_of(static_cast<Eigen::Index>(n));  // per variable
  std::vector<PoseParameters> candidate = poses;
  std::string why = "no convergence";
  while (summary.iterations < options.max_iterations) {
    if (!linearized) {
      cost = m.linearize(poses, weights, g, options.threads);
      linearized = true;
    }
    if (g.lpNorm<Eigen::Infinity>() <= options.gradient_tolerance) {
      why = "gradient tolerance reached";
      break;
    }
    if (radius < kMinRadius) {
      why = "trust region radius below its minimum";
      break;
    }
    ++summary.iterations;
    // (H + D / radius) delta = -g, damped and eliminated in place: the next step linearizes anew.
    auto* x = static_cast<double*>(m.H->x);
    for (size_t v = 0; v < m.variables; ++v) {
      for (int c = 0; c < 6; ++c) {
        double& d = x[m.diagonalSlot(v, c)];
        diagonal[6 * v + c] = std::clamp(d, kMinDiagonal, kMaxDiagonal);
        d += diagonal[6 * v + c] / radius;
      }
    }
    rhs_of = -g;
    const bool eliminated = m.eliminate(rhs_of);
    auto* rhs = static_cast<double*>(b->x);  // in A's order
    for (size_t k = 0; k < n; ++k) {
      if (m.permuted[k] != kNone) rhs[m.permuted[k]] = rhs_of[static_cast<Eigen::Index>(k)];
    }
    const auto factorization_start = std::chrono::steady_clock::now();
    const bool positive =
        eliminated && cholmod_l_factorize(m.H, m.L, &m.common) && m.common.status == CHOLMOD_OK;
    summary.factorization_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - factorization_start)
            .count();
    cholmod_dense* delta = positive ? cholmod_l_solve(CHOLMOD_A, m.L, b, &m.common) : nullptr;
    const bool solved = delta != nullptr;
    if (solved) {
      const auto* solution = static_cast<const double*>(delta->x);  // in A's order
      for (size_t k = 0; k < n; ++k) {
        if (m.permuted[k] != kNone) step[static_cast<Eigen::Index>(k)] = solution[m.permuted[k]];
      }
      cholmod_l_free_dense(&delta, &m.common);
      m.substituteBack(step);
    }
    linearized = false;
    bool taken = false;
    if (!solved && ++invalid_steps >= kMaxConsecutiveInvalidSteps) {
      why = "the damped normal equations could not be factorized";
      break;
    }
    if (solved) {
      double model_decrease = -step.dot(g);
      for (size_t k = 0; k < n; ++k) model_decrease += diagonal[k] / radius * step[k] * step[k];
      model_decrease *= 0.5;
      double x_norm_sq = 0.0;
      for (size_t p = 0; p < poses.size(); ++p) {
        candidate[p] = poses[p];
        x_norm_sq += poses[p].q.coeffs().squaredNorm() + poses[p].t.squaredNorm();
        const long v = m.variable[p];
        if (v == kNone) continue;
        const Eigen::Vector3d rotation_step = step.segment<3>(6 * v);
        m.rotation->Plus(poses[p].q.coeffs().data(), rotation_step.data(),
                         candidate[p].q.coeffs().data());
        candidate[p].t += step.segment<3>(6 * v + 3);
      }
      const double step_norm = step.norm();
      if (step_norm <=
          options.parameter_tolerance * (std::sqrt(x_norm_sq) + options.parameter_tolerance)) {
        why = "parameter tolerance reached";
        break;
      }
      const double new_cost = m.cost(candidate, weights, options.threads);
      if (std::isfinite(new_cost)) {
        invalid_steps = 0;
        const double decrease = cost - new_cost;
        const double rho = model_decrease > 0.0 ? decrease / model_decrease : -1.0;
        taken = rho > kMinRelativeDecrease;
        if (taken) {
          std::copy(candidate.begin(), candidate.end(), poses.begin());  // in place
          const double previous = cost;
          cost = new_cost;
          radius = std::min(kMaxRadius,
                            radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
          decrease_factor = 2.0;
          if (std::abs(decrease) <= options.function_tolerance * previous) {
            why = "function tolerance reached";
            break;
          }
        }
      } else if (++invalid_steps >= kMaxConsecutiveInvalidSteps) {
        why = "too many steps whose cost is not finite";
        break;
      }
    }
    if (!taken) {
      radius /= decrease_factor;
      decrease_factor *= 2.0;
    }
  }
  cholmod_l_free_dense(&b, &m.common);
  summary.final_cost = cost;
  return finish(why);
}

}  // namespace hydra_multi
