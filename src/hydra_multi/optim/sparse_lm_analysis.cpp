// SparseLevenbergMarquardt's analysis, once per pattern: the free poses, the chains and leaves
// eliminated before CHOLMOD, the blocks of H, their fill-reducing order and CHOLMOD's symbolic
// factorization of the rest.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

#include "hydra_multi/optim/fill_reducing_ordering.h"
#include "hydra_multi/optim/serial_openmp.h"
#include "hydra_multi/optim/sparse_lm_impl.h"
#include "hydra_multi/optim/suitesparse_blocks.h"

namespace hydra_multi {

using namespace sparse_lm;

namespace {

constexpr size_t kBothOrderingsFrom = 5000;  // variables
// Below this many eliminations they stay on one thread; a split leaving either thread less than
// kMinSplitShare of the work is not taken.
constexpr size_t kEliminationThreadsFrom = 2048;
constexpr double kMinSplitShare = 0.25;

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

void SparseLevenbergMarquardt::Impl::splitEliminations(size_t blocks) {
  elimination_split = 0;
  const size_t count = eliminations.size();
  if (count < kEliminationThreadsFrom) return;
  std::vector<long> elimination_of(variables, kNone);
  for (size_t k = 0; k < count; ++k) elimination_of[eliminations[k].v] = static_cast<long>(k);
  // The parts joined through eliminated variables (union-find over eliminations), each with its
  // last elimination.
  std::vector<size_t> parent(count);
  for (size_t k = 0; k < count; ++k) parent[k] = k;
  const auto root = [&](size_t k) {
    while (parent[k] != k) k = parent[k] = parent[parent[k]];
    return k;
  };
  for (size_t k = 0; k < count; ++k) {
    for (const long u : eliminations[k].u) {
      if (u == kNone || elimination_of[u] == kNone) continue;
      const size_t a = root(k), b = root(static_cast<size_t>(elimination_of[u]));
      if (a != b) parent[std::min(a, b)] = std::max(a, b);
    }
  }
  std::vector<size_t> last(count, 0);
  for (size_t k = 0; k < count; ++k) last[root(k)] = std::max(last[root(k)], k);
  // The split nearest half the work (an elimination's: one plus its neighbours) that no part
  // spans: every part begun before it has ended before it.
  const auto work = [&](size_t k) {
    return 1.0 + (eliminations[k].u[0] != kNone) + (eliminations[k].u[1] != kNone);
  };
  double total = 0.0;
  for (size_t k = 0; k < count; ++k) total += work(k);
  double before = 0.0, best_gap = total;
  size_t best = 0, ended = 0;
  for (size_t k = 0; k < count; ++k) {
    ended = std::max(ended, last[root(k)]);
    before += work(k);
    if (ended == k && std::abs(before - 0.5 * total) < best_gap) {
      best_gap = std::abs(before - 0.5 * total);
      best = k + 1;
    }
  }
  if (best == 0 || best_gap > (0.5 - kMinSplitShare) * total) return;
  elimination_split = best;
  // What the first thread writes of variables in A: their diagonal blocks and rhs segments, and
  // the blocks between two of them.
  // Room for every deferred write is reserved, so that the second thread never allocates.
  std::vector<char> variable_written(variables, 0), block_written(blocks, 0);
  const auto inA = [&](long u) { return u != kNone && elimination_of[u] == kNone; };
  size_t blocks_deferred = 0, rhs_deferred = 0;
  for (size_t k = 0; k < count; ++k) {
    Elimination& e = eliminations[k];
    e.deferred = 0;
    for (int n = 0; n < 2; ++n) {
      if (!inA(e.u[n])) continue;
      if (k < best) variable_written[e.u[n]] = 1;
      if (k >= best && variable_written[e.u[n]]) {
        e.deferred |= 1u << n;
        ++blocks_deferred;
        ++rhs_deferred;
      }
    }
    if (e.u01 == kNone || !inA(e.u[0]) || !inA(e.u[1])) continue;
    if (k < best) block_written[e.u01] = 1;
    if (k >= best && block_written[e.u01]) {
      e.deferred |= 4u;
      ++blocks_deferred;
    }
  }
  deferred_blocks.reserve(blocks_deferred);
  deferred_rhs.reserve(rhs_deferred);
}

cholmod_factor* sparse_lm::supernodalFromBlocks(const std::vector<std::vector<long>>& columns,
                                                const size_t scalar_nrelax[3],
                                                cholmod_common& common, double& fl, double& lnz) {
  using Int = SuiteSparse_long;
  const size_t blocks = columns.size(), n = 6 * blocks;
  cholmod_sparse* B = patternMatrix(columns, /*stype=*/-1, common);
  if (B == nullptr) return nullptr;
  const int supernodal = common.supernodal;
  const size_t kept_nrelax[3] = {common.nrelax[0], common.nrelax[1], common.nrelax[2]};
  const size_t block_nrelax[3] = {scalar_nrelax[0] / 6, scalar_nrelax[1] / 6, scalar_nrelax[2] / 6};
  std::copy(block_nrelax, block_nrelax + 3, common.nrelax);
  common.supernodal = CHOLMOD_SUPERNODAL;
  cholmod_factor* Lb = cholmod_l_analyze(B, &common);
  std::copy(kept_nrelax, kept_nrelax + 3, common.nrelax);
  common.supernodal = supernodal;
  cholmod_l_free_sparse(&B, &common);
  if (Lb == nullptr) return nullptr;
  const auto* counts = static_cast<const Int*>(Lb->ColCount);
  fl = lnz = 0.0;
  for (size_t c = 0; c < blocks; ++c) {
    for (int i = 0; i < 6; ++i) {
      const double count = 6.0 * double(counts[c]) - i;
      fl += count * count;
      lnz += count;
    }
  }
  cholmod_factor* L = nullptr;
  if (Lb->is_super && fl >= common.supernodal_switch * lnz) {
    L = cholmod_l_allocate_factor(n, &common);
    const size_t nsuper = Lb->nsuper;
    const auto* super_b = static_cast<const Int*>(Lb->super);
    const auto* pi_b = static_cast<const Int*>(Lb->pi);
    const auto* s_b = static_cast<const Int*>(Lb->s);
    const size_t rows_b = static_cast<size_t>(pi_b[nsuper]);
    Int *super = nullptr, *pi = nullptr, *px = nullptr, *s = nullptr;
    if (L != nullptr) {
      super = static_cast<Int*>(cholmod_l_malloc(nsuper + 1, sizeof(Int), &common));
      pi = static_cast<Int*>(cholmod_l_malloc(nsuper + 1, sizeof(Int), &common));
      px = static_cast<Int*>(cholmod_l_malloc(nsuper + 1, sizeof(Int), &common));
      s = static_cast<Int*>(
          cholmod_l_malloc(std::max<size_t>(6 * rows_b, 1), sizeof(Int), &common));
    }
    if (super == nullptr || pi == nullptr || px == nullptr || s == nullptr) {
      cholmod_l_free(nsuper + 1, sizeof(Int), super, &common);
      cholmod_l_free(nsuper + 1, sizeof(Int), pi, &common);
      cholmod_l_free(nsuper + 1, sizeof(Int), px, &common);
      cholmod_l_free(std::max<size_t>(6 * rows_b, 1), sizeof(Int), s, &common);
      cholmod_l_free_factor(&L, &common);
    } else {
      auto* scalar_counts = static_cast<Int*>(L->ColCount);
      for (size_t c = 0; c < blocks; ++c) {
        for (int i = 0; i < 6; ++i) scalar_counts[6 * c + i] = 6 * counts[c] - i;
      }
      px[0] = 0;
      for (size_t k = 0; k <= nsuper; ++k) {
        super[k] = 6 * super_b[k];
        pi[k] = 6 * pi_b[k];
        if (k > 0) px[k] = px[k - 1] + (super[k] - super[k - 1]) * (pi[k] - pi[k - 1]);
      }
      for (size_t q = 0; q < rows_b; ++q) {
        for (int i = 0; i < 6; ++i) s[6 * q + i] = 6 * s_b[q] + i;
      }
      L->super = super;
      L->pi = pi;
      L->px = px;
      L->s = s;
      L->nsuper = nsuper;
      L->ssize = std::max<size_t>(6 * rows_b, 1);
      L->xsize = static_cast<size_t>(px[nsuper]);
      L->maxcsize = 36 * Lb->maxcsize;
      L->maxesize = 6 * Lb->maxesize;
      L->is_super = true;
      L->is_ll = Lb->is_ll;
      L->is_monotonic = Lb->is_monotonic;
      L->ordering = CHOLMOD_NATURAL;
      L->minor = n;
    }
  }
  cholmod_l_free_factor(&Lb, &common);
  return L;
}

void SparseLevenbergMarquardt::Impl::analyze(size_t num_poses, const std::vector<bool>& fixed) {
  Impl& m = *this;
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
  m.splitEliminations(block_at.size());
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
  // A as a CHOLMOD matrix (values unset, as each linearization sets them all first; only the
  // pattern for `values` false) and, with `values`, `column` and `transposed`, the eliminated
  // blocks' values after A's. An entry (i, j) of A's block at (R, C) is H's entry (i, j) of its
  // block where R is that block's row variable and R != C, else (j, i); a diagonal block keeps one
  // triangle. `columns`: placeBlocks(position, stype).
  const auto store = [&](const std::vector<long>& position, const auto& columns, int stype,
                         bool values) {
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
  const auto lower = placeBlocks(position, -1);
  m.H = store(position, lower, -1, true);
  if (m.H == nullptr) return;
  m.common.supernodal = CHOLMOD_AUTO;
  m.common.final_asis = 1;  // the factor as computed: no conversion after each factorization
  m.common.postorder = 0;
  m.common.nmethods = 1;
  m.common.method[0].ordering = CHOLMOD_NATURAL;
  // On the block pattern where the factor is supernodal (the scalar pattern has 36 entries a
  // block); else CHOLMOD's own analysis, which then makes it simplicial.
  std::vector<std::vector<long>> block_rows(m.reduced);
  for (size_t c = 0; c < m.reduced; ++c) {
    for (const auto& [r, k] : lower[c]) block_rows[c].push_back(r);
  }
  double fl = 0.0, lnz = 0.0;
  m.L = sparse_lm::supernodalFromBlocks(block_rows, m.common.nrelax, m.common, fl, lnz);
  if (m.L == nullptr) {
    m.L = cholmod_l_analyze(m.H, &m.common);
    fl = m.common.fl;
  }
  if (m.L != nullptr) m.flops = fl + elimination_flops;
  if (m.L != nullptr && m.L->is_super && m.L->ordering == CHOLMOD_NATURAL)
    m.supernodal = std::make_unique<SupernodalCholesky>(*m.L);
  if (m.L != nullptr && !m.L->is_super) {
    cholmod_l_free_sparse(&m.H, &m.common);
    m.H = store(position, placeBlocks(position, 1), 1, true);
  }
}

void SparseLevenbergMarquardt::Impl::allocateFactor() {
  if (L == nullptr || !L->is_super || L->xtype != CHOLMOD_PATTERN) return;
  // A block not kept for reuse is freed at once, and its pages come from the allocating thread's
  // arena: faulted in here, they would be faulted in again by the solve's own.
  if (!keptForReuse(L->xsize * sizeof(double))) return;
  const SerialOpenMp serial;
  if (allocateValues()) std::memset(L->x, 0, L->xsize * sizeof(double));
}

bool SparseLevenbergMarquardt::Impl::allocateValues() {
  if (L->xtype != CHOLMOD_PATTERN) return true;
  // The numeric supernodal LL' factor cholmod_l_factorize would make of it on its first call.
  return cholmod_l_change_factor(CHOLMOD_REAL, true, true, true, true, L, &common) &&
         L->x != nullptr;
}

bool SparseLevenbergMarquardt::Impl::factorize(int threads, double single_from_flops,
                                               LmSummary& summary) {
  if (supernodal == nullptr)
    return cholmod_l_factorize(H, L, &common) && common.status == CHOLMOD_OK;
  // In single precision where large enough (L then needs no values of its own); where that
  // fails, in double.
  bool single = false;
  if (single_from_flops >= 0.0 && supernodal->flops() >= single_from_flops) {
    single = supernodal->factorize(*H, *L, threads, true);
    ++(single ? summary.single_precision_factorizations : summary.single_precision_fallbacks);
  }
  if (!single && !(allocateValues() && supernodal->factorize(*H, *L, threads))) return false;
  L->minor = L->n;
  return true;
}

void SparseLevenbergMarquardt::Impl::freeFactorValues() {
  if (L == nullptr || !L->is_super || L->xtype == CHOLMOD_PATTERN) return;
  cholmod_l_change_factor(CHOLMOD_PATTERN, true, true, true, true, L, &common);
}

}  // namespace hydra_multi
