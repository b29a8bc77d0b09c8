#include "hydra_multi/optim/supernodal_cholesky.h"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <new>
#include <numeric>
#include <system_error>
#include <thread>

#include "hydra_multi/core/parallel.h"

extern "C" {
// BLAS and LAPACK (Fortran symbols, 32-bit integers), as CHOLMOD calls them.
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
            const double* beta, double* c, const int* ldc);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const double* alpha, const double* a, const int* lda, double* b,
            const int* ldb);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a,
            const int* lda, double* x, const int* incx);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* x, const int* incx, const double* beta, double* y,
            const int* incy);
void ssyrk_(const char* uplo, const char* trans, const int* n, const int* k, const float* alpha,
            const float* a, const int* lda, const float* beta, float* c, const int* ldc);
void sgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const float* alpha, const float* a, const int* lda, const float* b, const int* ldb,
            const float* beta, float* c, const int* ldc);
void spotrf_(const char* uplo, const int* n, float* a, const int* lda, int* info);
void strsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const float* alpha, const float* a, const int* lda, float* b,
            const int* ldb);
void strsv_(const char* uplo, const char* trans, const char* diag, const int* n, const float* a,
            const int* lda, float* x, const int* incx);
void sgemv_(const char* trans, const int* m, const int* n, const float* alpha, const float* a,
            const int* lda, const float* x, const int* incx, const float* beta, float* y,
            const int* incy);
}

namespace hydra_multi {
namespace {

// Below this many flops a factorization stays on one thread: starting the second costs more.
constexpr double kTwoThreadsFrom = 2e7;
// The cut is kept only where its longer part is at most this share of the whole.
constexpr double kSplitShare = 0.9;
// Subtrees the cut may move into its top part, heaviest first.
constexpr int kCutSteps = 32;

// The dense calls in double or single precision, by the values' type.
template <typename T>
struct Dense;
template <>
struct Dense<double> {
  static constexpr auto syrk = dsyrk_;
  static constexpr auto gemm = dgemm_;
  static constexpr auto potrf = dpotrf_;
  static constexpr auto trsm = dtrsm_;
  static constexpr auto trsv = dtrsv_;
  static constexpr auto gemv = dgemv_;
};
template <>
struct Dense<float> {
  static constexpr auto syrk = ssyrk_;
  static constexpr auto gemm = sgemm_;
  static constexpr auto potrf = spotrf_;
  static constexpr auto trsm = strsm_;
  static constexpr auto trsv = strsv_;
  static constexpr auto gemv = sgemv_;
};

std::mutex& blasBufferMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

SupernodalCholesky::SupernodalCholesky(const cholmod_factor& symbolic) {
  const Int supernodes = static_cast<Int>(symbolic.nsuper);
  const auto* super = static_cast<const Int*>(symbolic.super);
  const auto* pi = static_cast<const Int*>(symbolic.pi);
  const auto* rows = static_cast<const Int*>(symbolic.s);
  owner_.resize(symbolic.n);
  for (Int s = 0; s < supernodes; ++s) {
    for (Int k = super[s]; k < super[s + 1]; ++k) owner_[k] = s;
  }
  // Work per supernode: its own dpotrf and dtrsm, and the updates it takes from its descendants.
  std::vector<Int> parent(supernodes, -1);
  std::vector<double> work(supernodes, 0.0);
  for (Int d = 0; d < supernodes; ++d) {
    const double columns = double(super[d + 1] - super[d]);
    const Int end = pi[d + 1];
    max_rows_ = std::max<size_t>(max_rows_, end - pi[d]);
    work[d] += columns * columns * columns / 3.0 + columns * columns * double(end - pi[d]);
    Int p = pi[d] + (super[d + 1] - super[d]);
    if (p < end) parent[d] = owner_[rows[p]];
    while (p < end) {
      const Int s = owner_[rows[p]];
      Int q = p;
      while (q < end && owner_[rows[q]] == s) ++q;
      const double in_s = double(q - p), below = double(end - p);
      max_update_ = std::max<size_t>(max_update_, size_t(in_s * below));
      work[s] += 2.0 * columns * in_s * below;
      p = q;
    }
  }
  for (const double w : work) total_flops_ += w;

  // The cut: subtrees in two sets, balanced largest first, below a top part that grows by the
  // heaviest subtree while that shortens the longer part.
  std::vector<double> subtree(work);
  std::vector<std::vector<Int>> children(supernodes);
  std::vector<Int> frontier, top, best_top;
  for (Int s = 0; s < supernodes; ++s) {  // a parent comes after its children
    if (parent[s] >= 0) {
      subtree[parent[s]] += subtree[s];
      children[parent[s]].push_back(s);
    } else {
      frontier.push_back(s);
    }
  }
  std::vector<Int> best_tasks;
  double top_work = 0.0, best_span = total_flops_ + 1.0;
  for (int step = 0; step < kCutSteps && !frontier.empty(); ++step) {
    std::sort(frontier.begin(), frontier.end(), [&](Int a, Int b) {
      return subtree[a] > subtree[b] || (subtree[a] == subtree[b] && a < b);
    });
    double load[2] = {0.0, 0.0};  // each subtree to the thread free first, largest first
    for (const Int s : frontier) load[load[1] < load[0] ? 1 : 0] += subtree[s];
    const double span = top_work + std::max(load[0], load[1]);
    if (span < best_span && frontier.size() > 1) {
      best_span = span;
      best_top = top;
      best_tasks = frontier;
    }
    const Int heaviest = frontier.front();
    if (children[heaviest].empty()) break;
    frontier.erase(frontier.begin());
    frontier.insert(frontier.end(), children[heaviest].begin(), children[heaviest].end());
    top.push_back(heaviest);
    top_work += work[heaviest];
  }
  two_threads_ = total_flops_ >= kTwoThreadsFrom && best_span <= kSplitShare * total_flops_;
  task_.assign(supernodes, kAll);
  if (two_threads_) {
    for (const Int s : best_top) task_[s] = kTop;
    for (size_t t = 0; t < best_tasks.size(); ++t) task_[best_tasks[t]] = static_cast<int32_t>(t);
    for (Int s = supernodes - 1; s >= 0; --s) {
      if (task_[s] == kAll) task_[s] = task_[parent[s]];
    }
    // Each task's supernodes in order, one after another.
    task_start_.assign(best_tasks.size() + 1, 0);
    for (Int s = 0; s < supernodes; ++s) {
      if (task_[s] >= 0) ++task_start_[task_[s] + 1];
    }
    for (size_t t = 0; t < best_tasks.size(); ++t) task_start_[t + 1] += task_start_[t];
    task_members_.resize(task_start_.back());
    std::vector<Int> at(task_start_.begin(), task_start_.end() - 1);
    for (Int s = 0; s < supernodes; ++s) {
      if (task_[s] >= 0) task_members_[at[task_[s]]++] = s;
      if (task_[s] == kTop) top_.push_back(s);
    }
    // Per subtree supernode, its rows below that are its subtree's (the first ones: ancestors in
    // the top part come after); the rest take a place each in the forward substitution's buffer.
    own_below_.assign(supernodes, 0);
    top_update_start_.assign(best_tasks.size() + 1, 0);
    for (size_t t = 0; t < best_tasks.size(); ++t) {
      size_t places = 0;
      for (size_t k = task_start_[t]; k < task_start_[t + 1]; ++k) {
        const Int m = task_members_[k];
        Int p = pi[m] + (super[m + 1] - super[m]);
        const Int first_below = p;
        while (p < pi[m + 1] && task_[owner_[rows[p]]] != kTop) ++p;
        own_below_[m] = p - first_below;
        places += pi[m + 1] - p;
      }
      top_update_start_[t + 1] = top_update_start_[t] + places;
    }
  }
  every_.resize(supernodes);
  std::iota(every_.begin(), every_.end(), Int{0});
  next_.assign(supernodes, -1);
  lpos_.assign(supernodes, 0);
  linked_.assign(supernodes, Linked{});
}

bool SupernodalCholesky::factorize(const cholmod_sparse& A, cholmod_factor& L, int threads,
                                   bool single) {
  single_ = single;
  if (single && single_size_ < L.xsize) {
    SuiteSparse_free(single_values_);
    single_values_ = static_cast<float*>(SuiteSparse_malloc(L.xsize, sizeof(float)));
    single_size_ = single_values_ != nullptr ? L.xsize : 0;
    if (single_values_ == nullptr) throw std::bad_alloc();
  }
  return single ? factorizeIn<float>(A, L, threads) : factorizeIn<double>(A, L, threads);
}

SupernodalCholesky::~SupernodalCholesky() { SuiteSparse_free(single_values_); }

template <typename T>
T* SupernodalCholesky::valuesOf(const cholmod_factor& L) const {
  if constexpr (std::is_same_v<T, float>) {
    return single_values_;
  } else {
    return static_cast<double*>(L.x);
  }
}

template <typename T>
bool SupernodalCholesky::factorizeIn(const cholmod_sparse& A, cholmod_factor& L, int threads) {
  const size_t supernodes = L.nsuper;
  for (Workspace& work : work_) {
    if (work.map.empty()) {
      work.map.assign(L.n, 0);
      work.relative.assign(max_rows_, 0);
    }
    if (work.updates<T>().empty()) work.updates<T>().assign(std::max<size_t>(max_update_, 1), 0);
    if (!two_threads_) break;
  }
  std::vector<Int> head(supernodes, -1);
  factorized_ = 0;
  if (threads < 2 || !two_threads_)
    return factorPart<T>(A, L, every_.data(), every_.size(), false, head, work_[0]);
  // The subtrees, largest first, each to the thread free first; then the top part.
  std::vector<Int> head_1(supernodes, -1);
  std::atomic<size_t> next_task{0};
  std::atomic<bool> stop{false};
  bool done[2] = {true, true};
  std::exception_ptr failed[2];
  const auto run = [&](int thread, std::vector<Int>& lists) {
    try {
      for (size_t t = next_task++; t + 1 < task_start_.size() && !stop; t = next_task++) {
        if (!factorPart<T>(A, L, &task_members_[task_start_[t]],
                           task_start_[t + 1] - task_start_[t], false, lists, work_[thread])) {
          done[thread] = false;
          stop = true;
        }
      }
    } catch (...) {
      failed[thread] = std::current_exception();
      stop = true;
    }
  };
  try {
    std::thread second(run, 1, std::ref(head_1));
    run(0, head);
    second.join();
  } catch (const std::system_error&) {  // no second thread: nothing done yet, all on this one
    return factorPart<T>(A, L, every_.data(), every_.size(), false, head, work_[0]);
  }
  for (const std::exception_ptr& failure : failed) {
    if (failure) std::rethrow_exception(failure);
  }
  if (!done[0] || !done[1]) return false;
  // The top part's lists: the second thread's after the first's, reordered as they are taken.
  for (size_t s = 0; s < supernodes; ++s) {
    if (task_[s] != kTop || head_1[s] < 0) continue;
    if (head[s] < 0) {
      head[s] = head_1[s];
      continue;
    }
    Int tail = head[s];
    while (next_[tail] >= 0) tail = next_[tail];
    next_[tail] = head_1[s];
  }
  return factorPart<T>(A, L, top_.data(), top_.size(), true, head, work_[0]);
}

template <typename T>
void SupernodalCholesky::substitute(const cholmod_factor& L, const T* values, Int s, bool forward,
                                    T* x, T* gathered, Int own, T* top_updates) {
  const auto* super = static_cast<const Int*>(L.super);
  const auto* pi = static_cast<const Int*>(L.pi);
  const auto* rows = static_cast<const Int*>(L.s) + pi[s];
  const T* Ls = values + static_cast<const Int*>(L.px)[s];
  const int columns = static_cast<int>(super[s + 1] - super[s]);
  const int height = static_cast<int>(pi[s + 1] - pi[s]), below = height - columns;
  const int one = 1;
  const T minus_one = -1, plus_one = 1;
  T* x1 = x + super[s];
  if (forward) {
    // x1 <- L1^-1 x1, then E <- E - L2 x1, scattered back; past `own` rows, -L2 x1 to the buffer
    const int kept = own < 0 ? below : static_cast<int>(own);
    for (int i = 0; i < kept; ++i) gathered[i] = x[rows[columns + i]];
    std::fill(gathered + kept, gathered + below, T{0});
    Dense<T>::trsv("L", "N", "N", &columns, Ls, &height, x1, &one);
    Dense<T>::gemv("N", &below, &columns, &minus_one, Ls + columns, &height, x1, &one, &plus_one,
                   gathered, &one);
    for (int i = 0; i < kept; ++i) x[rows[columns + i]] = gathered[i];
    std::copy(gathered + kept, gathered + below, top_updates);
  } else {
    // x1 <- x1 - L2^T E, then x1 <- L1^-T x1
    for (int i = 0; i < below; ++i) gathered[i] = x[rows[columns + i]];
    Dense<T>::gemv("C", &below, &columns, &minus_one, Ls + columns, &height, gathered, &one,
                   &plus_one, x1, &one);
    Dense<T>::trsv("L", "C", "N", &columns, Ls, &height, x1, &one);
  }
}

void SupernodalCholesky::runTasks(int threads, const std::function<void(size_t, int)>& task) {
  std::atomic<size_t> next_task{0};
  const auto run = [&](int thread) {
    for (size_t t = next_task++; t + 1 < task_start_.size(); t = next_task++) task(t, thread);
  };
  if (threads < 2) return run(0);
  try {
    std::thread second(run, 1);
    run(0);
    second.join();
  } catch (const std::system_error&) {  // no second thread: the first takes every subtree
    run(0);
  }
}

void SupernodalCholesky::forwardInTasks(const cholmod_factor& L, float* x, int threads) {
  // The subtrees, each with its updates to the top part's rows in places of its own, added in the
  // order of the subtrees; then the top part.
  const auto* super = static_cast<const Int*>(L.super);
  const auto* pi = static_cast<const Int*>(L.pi);
  const auto* rows = static_cast<const Int*>(L.s);
  const float* values = single_values_;
  top_updates_.resize(top_update_start_.back());
  runTasks(threads, [&](size_t t, int thread) {
    float* buffer = work_[thread].gatheredRows<float>().data();
    float* updates = top_updates_.data() + top_update_start_[t];
    for (size_t k = task_start_[t]; k < task_start_[t + 1]; ++k) {
      const Int s = task_members_[k];
      substitute(L, values, s, true, x, buffer, own_below_[s], updates);
      updates += (pi[s + 1] - pi[s]) - (super[s + 1] - super[s]) - own_below_[s];
    }
  });
  const float* update = top_updates_.data();
  for (const Int s : task_members_) {
    for (Int p = pi[s] + (super[s + 1] - super[s]) + own_below_[s]; p < pi[s + 1]; ++p)
      x[rows[p]] += *update++;
  }
  float* gathered = work_[0].gatheredRows<float>().data();
  for (const Int s : top_) substitute(L, values, s, true, x, gathered);
}

template <typename T>
void SupernodalCholesky::solveIn(const cholmod_factor& L, T* x, int threads) {
  const Int supernodes = static_cast<Int>(L.nsuper);
  const T* values = valuesOf<T>(L);
  for (Workspace& work : work_) work.gatheredRows<T>().resize(max_rows_);
  T* gathered = work_[0].gatheredRows<T>().data();
  bool forward_done = false;
  if constexpr (std::is_same_v<T, float>) {
    if (two_threads_) {
      forwardInTasks(L, x, threads);
      forward_done = true;
    }
  }
  if (!forward_done) {
    for (Int s = 0; s < supernodes; ++s) substitute(L, values, s, true, x, gathered);
  }
  if (threads < 2 || !two_threads_) {
    for (Int s = supernodes; s-- > 0;) substitute(L, values, s, false, x, gathered);
    return;
  }
  // The top part, whose rows are its own; then each subtree, whose rows are its own or the top's.
  for (size_t k = top_.size(); k-- > 0;) substitute(L, values, top_[k], false, x, gathered);
  runTasks(threads, [&](size_t t, int thread) {
    T* buffer = work_[thread].gatheredRows<T>().data();
    for (size_t k = task_start_[t + 1]; k-- > task_start_[t];)
      substitute(L, values, task_members_[k], false, x, buffer);
  });
}

void SupernodalCholesky::solve(const cholmod_factor& L, double* x, int threads) {
  if (!single_) return solveIn(L, x, threads);
  single_x_.assign(x, x + L.n);
  solveIn(L, single_x_.data(), threads);
  std::copy(single_x_.begin(), single_x_.end(), x);
}

void SupernodalCholesky::solve(const cholmod_sparse& A, const cholmod_factor& L, double* x,
                               int threads) {
  if (!single_) return solveIn(L, x, threads);
  const size_t n = L.n;
  refined_.assign(x, x + n);  // b
  solve(L, x, threads);
  // r = b - A x, A symmetric by its lower triangle; x += L^-T L^-1 r. A's columns in two halves
  // by their entries, the first half's terms in the second half's rows summed apart, then added:
  // the same sums on one thread or two.
  const auto* Ap = static_cast<const Int*>(A.p);
  const auto* Anz = static_cast<const Int*>(A.nz);
  const auto* Ai = static_cast<const Int*>(A.i);
  const auto* Ax = static_cast<const double*>(A.x);
  const Int columns = static_cast<Int>(A.ncol);
  const Int half = static_cast<Int>(std::lower_bound(Ap, Ap + columns, Ap[columns] / 2) - Ap);
  spilled_.assign(columns - half, 0.0);
  const auto part = [&](Int first, Int last) {
    for (Int j = first; j < last; ++j) {
      const Int end = A.packed ? Ap[j + 1] : Ap[j] + Anz[j];
      double along_j = 0.0;
      for (Int q = Ap[j]; q < end; ++q) {
        const Int i = Ai[q];
        if (i < j) continue;
        along_j += Ax[q] * x[i];
        if (i == j) continue;
        if (j < half && i >= half) {
          spilled_[i - half] += Ax[q] * x[j];
        } else {
          refined_[i] -= Ax[q] * x[j];
        }
      }
      refined_[j] -= along_j;
    }
  };
  if (threads >= 2 && two_threads_) {
    runOnThreads(2, [&](size_t t) { t == 0 ? part(0, half) : part(half, columns); });
  } else {
    part(0, half);
    part(half, columns);
  }
  for (Int i = half; i < columns; ++i) refined_[i] -= spilled_[i - half];
  single_x_.assign(refined_.begin(), refined_.end());
  solveIn(L, single_x_.data(), threads);
  for (size_t k = 0; k < n; ++k) x[k] += single_x_[k];
}

template <typename T>
bool SupernodalCholesky::factorPart(const cholmod_sparse& A, cholmod_factor& L, const Int* only,
                                    size_t count, bool order_lists, std::vector<Int>& head,
                                    Workspace& work) {
  const auto* super = static_cast<const Int*>(L.super);
  const auto* pi = static_cast<const Int*>(L.pi);
  const auto* px = static_cast<const Int*>(L.px);
  const auto* rows = static_cast<const Int*>(L.s);
  T* Lx = valuesOf<T>(L);
  const auto* Ap = static_cast<const Int*>(A.p);
  const auto* Anz = static_cast<const Int*>(A.nz);
  const auto* Ai = static_cast<const Int*>(A.i);
  const auto* Ax = static_cast<const double*>(A.x);
  const T one = 1, zero = 0;
  std::vector<Int> descendants;
  for (size_t at = 0; at < count; ++at) {
    const Int s = only[at];
    ++factorized_;
    const Int k1 = super[s], k2 = super[s + 1], columns = k2 - k1;
    const Int first_row = pi[s], height = pi[s + 1] - first_row;
    for (Int k = 0; k < height; ++k) work.map[rows[first_row + k]] = k;
    T* Ls = Lx + px[s];
    std::memset(Ls, 0, sizeof(T) * static_cast<size_t>(height * columns));
    for (Int j = k1; j < k2; ++j) {
      T* column = Ls + (j - k1) * height;
      const Int end = A.packed ? Ap[j + 1] : Ap[j] + Anz[j];
      for (Int q = Ap[j]; q < end; ++q) {
        if (Ai[q] < j) continue;
        if constexpr (std::is_same_v<T, float>) {  // beyond floats' range: no factor in them
          if (!(std::fabs(Ax[q]) <= std::numeric_limits<float>::max())) return false;
        }
        column[work.map[Ai[q]]] = static_cast<T>(Ax[q]);
      }
    }
    descendants.clear();
    for (Int d = head[s]; d >= 0; d = next_[d]) descendants.push_back(d);
    head[s] = -1;
    if (order_lists) {  // as one thread would have put them: the latest first
      std::sort(descendants.begin(), descendants.end(), [&](Int a, Int b) {
        return linked_[a].at > linked_[b].at ||
               (linked_[a].at == linked_[b].at && linked_[a].nth > linked_[b].nth);
      });
    }
    int64_t nth = 0;
    const auto link = [&](Int d, Int row_at) {
      const Int to = owner_[rows[row_at]];
      next_[d] = head[to];
      head[to] = d;
      linked_[d] = Linked{s, nth++};
    };
    for (const Int d : descendants) {
      const Int d_first = pi[d], d_height = pi[d + 1] - d_first;
      const Int p1 = d_first + lpos_[d];
      Int p2 = p1;
      while (p2 < d_first + d_height && rows[p2] < k2) ++p2;
      const int in_s = static_cast<int>(p2 - p1);
      const int below = static_cast<int>(d_first + d_height - p1);
      const int after_s = below - in_s;
      const int d_columns = static_cast<int>(super[d + 1] - super[d]);
      const int ld = static_cast<int>(d_height);
      const T* Ld = Lx + px[d] + lpos_[d];
      T* C = work.updates<T>().data();
      Dense<T>::syrk("L", "N", &in_s, &d_columns, &one, Ld, &ld, &zero, C, &below);
      if (after_s > 0) {
        Dense<T>::gemm("N", "C", &after_s, &in_s, &d_columns, &one, Ld + in_s, &ld, Ld, &ld, &zero,
                       C + in_s, &below);
      }
      for (int i = 0; i < below; ++i) work.relative[i] = work.map[rows[p1 + i]];
      for (int j = 0; j < in_s; ++j) {
        T* column = Ls + work.relative[j] * height;
        const T* c = C + static_cast<ptrdiff_t>(j) * below;
        for (int i = j; i < below; ++i) column[work.relative[i]] -= c[i];
      }
      lpos_[d] = p2 - d_first;
      if (lpos_[d] < d_height) link(d, p2);
    }
    const int n = static_cast<int>(columns), ld = static_cast<int>(height);
    const int m = static_cast<int>(height - columns);
    int info = 0;
    Dense<T>::potrf("L", &n, Ls, &ld, &info);
    if (info != 0) return false;
    if (m > 0) {
      Dense<T>::trsm("R", "L", "C", "N", &m, &n, &one, Ls, &ld, Ls + columns, &ld);
      lpos_[s] = columns;
      link(s, first_row + columns);
    }
  }
  return true;
}

}  // namespace hydra_multi

// OpenBLAS's work buffers (its internal allocator, which every level-3 and LAPACK call of its
// takes through the PLT): taken under one lock, since Debian's serial build takes them unlocked.
// The executables export these two (optim's link options). Without OpenBLAS nothing calls them.
extern "C" void* blas_memory_alloc(int procpos) {
  using Alloc = void* (*)(int);
  static const Alloc next = reinterpret_cast<Alloc>(dlsym(RTLD_NEXT, "blas_memory_alloc"));
  if (next == nullptr) return nullptr;
  const std::lock_guard<std::mutex> lock(hydra_multi::blasBufferMutex());
  return next(procpos);
}

extern "C" void blas_memory_free(void* area) {
  using Free = void (*)(void*);
  static const Free next = reinterpret_cast<Free>(dlsym(RTLD_NEXT, "blas_memory_free"));
  if (next == nullptr) return;
  const std::lock_guard<std::mutex> lock(hydra_multi::blasBufferMutex());
  next(area);
}
