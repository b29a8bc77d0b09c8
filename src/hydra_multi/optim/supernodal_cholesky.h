#pragma once
// The numeric supernodal Cholesky factorization A = L L^T on CHOLMOD's symbolic supernodal factor
// of A (A stored as its lower triangle in the factor's own order: no permutation), left-looking
// as CHOLMOD's (cholmod_super_numeric): per supernode s, in column order, A's columns scattered
// in, the update L_d(rows >= s) L_d(rows of s)^T of each descendant d with rows in s subtracted
// (dsyrk, dgemm), then L_ss = chol(.) (dpotrf) and the rows below it solved (dtrsm).
// On two threads the supernodal elimination tree is cut into a top part and disjoint subtrees:
// the cut two threads would end soonest by a flop count per supernode (updates included), each
// subtree taken, largest first, by the thread free first. The threads take the subtrees so, then
// one does the top part. Every supernode takes its descendants in the order one thread takes
// them, so the factor is the same to the bit on one thread or two, and the same as CHOLMOD's.
// In single precision the same steps run on floats (ssyrk, sgemm, spotrf, strsm), the factor's
// values then this object's own floats (L needs none); a solve refines the floats' solution once
// in double: x0 = (L L^T)^-1 b, x = x0 + (L L^T)^-1 (b - A x0).
// Debian's serial OpenBLAS does not lock its pool of work buffers for callers on several
// threads; while a factorization runs on two, each buffer is taken under a lock (its
// blas_memory_alloc, interposed), so two dense calls never share one.

#include <cholmod.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <vector>

namespace hydra_multi {

class SupernodalCholesky {
 public:
  /// The plan for `symbolic` (supernodal, in its natural order): its tree, a flop count per
  /// supernode and the cut for two threads.
  explicit SupernodalCholesky(const cholmod_factor& symbolic);
  ~SupernodalCholesky();
  SupernodalCholesky(const SupernodalCholesky&) = delete;
  SupernodalCholesky& operator=(const SupernodalCholesky&) = delete;

  /// L <- the factor of A, on `threads` threads (two at most; one where the cut gains little).
  /// L: the factor the plan was made for, its numeric values allocated (real, supernodal LL'),
  /// except with `single`: the factor in single precision, in floats of this object's own
  /// (singleValues(); allocated through SuiteSparse's allocator, in L's layout).
  /// False where A is not positive definite (a pivot not above zero), or in single precision where
  /// an entry of A is beyond floats' range; L is then unusable.
  bool factorize(const cholmod_sparse& A, cholmod_factor& L, int threads, bool single = false);

  /// x <- A^-1 x by the factor L of A that factorize() made: L's forward then backward
  /// substitution, supernode by supernode with the dense calls of CHOLMOD's (cholmod_l_solve on
  /// an LL' supernodal factor), so the same solution to the bit. The backward substitution, on
  /// two threads where the factorization splits: the top part first, then the subtrees.
  /// x: in L's order, L.n values. A factor in single precision solves in floats, its forward
  /// substitution on two threads too where the factorization splits: the subtrees, their updates
  /// to the top part's rows then added in the subtrees' order, then the top part (the same
  /// solution on one thread and on two, not CHOLMOD's order of additions).
  void solve(const cholmod_factor& L, double* x, int threads);
  /// The same; a factor in single precision then refines its solution once by A, the matrix it
  /// factorized (its lower triangle): x += (L L^T)^-1 (b - A x), the residual in double, by A's
  /// columns in two halves (on two threads where the factorization splits).
  void solve(const cholmod_sparse& A, const cholmod_factor& L, double* x, int threads);
  /// Whether the last factorize() was in single precision, and its floats (L's layout, L.xsize).
  bool single() const { return single_; }
  const float* singleValues() const { return single_values_; }

  /// Whether two threads are used: at least 2e7 flops, and by the flop count two threads taking
  /// the cut's subtrees, then the top part, end within 90 % of one thread's time.
  bool splits() const { return two_threads_; }
  double flops() const { return total_flops_; }
  /// The supernodes the last factorize() factorized: each once, L.nsuper where it ended well.
  size_t factorized() const { return factorized_; }

 private:
  using Int = SuiteSparse_long;
  struct Workspace {
    std::vector<Int> map, relative;
    std::vector<double> update, gathered;
    std::vector<float> update_single, gathered_single;
    std::vector<double> panel;               // a diagonal block in double (single precision)
    std::vector<float> inverse, rows_below;  // its inverse, and L21 as sgemm writes it
    template <typename T>
    std::vector<T>& updates() {
      return pick<T>(update, update_single);
    }
    template <typename T>
    std::vector<T>& gatheredRows() {
      return pick<T>(gathered, gathered_single);
    }
    template <typename T>
    static std::vector<T>& pick(std::vector<double>& d, std::vector<float>& f) {
      if constexpr (std::is_same_v<T, float>) {
        return f;
      } else {
        return d;
      }
    }
  };
  // When a descendant was put on its next supernode's list: while supernode `at` was done, as
  // the `nth` put then. One thread's lists hold their descendants in descending order of it.
  struct Linked {
    Int at = -1;
    int64_t nth = 0;
  };
  // The forward substitution through supernode s, or the backward one; `gathered`: a buffer of
  // the supernode's rows below its columns.
  // In the forward one, of the rows below only the first `own` (all where negative) are updated
  // in x; the others' updates (-L2 x1) go to `top_updates`, in order.
  template <typename T>
  static void substitute(const cholmod_factor& L, const T* values, Int s, bool forward, T* x,
                         T* gathered, Int own = -1, T* top_updates = nullptr);
  // Runs task(t, thread) for every subtree t, each on the thread free first.
  void runTasks(int threads, const std::function<void(size_t, int)>& task);
  // The forward substitution in floats with the subtrees on `threads` threads: the same result on
  // one thread and on two.
  void forwardInTasks(const cholmod_factor& L, float* x, int threads);
  template <typename T>
  T* valuesOf(const cholmod_factor& L) const;  // L.x, or the floats
  template <typename T>
  void solveIn(const cholmod_factor& L, T* x, int threads);
  template <typename T>
  bool factorizeIn(const cholmod_sparse& A, cholmod_factor& L, int threads);
  // Factorizes the `count` supernodes at `only` in order (every_: all of them), with the
  // descendants' lists `head`; `order_lists`: each list sorted as one thread would have made it.
  template <typename T>
  bool factorPart(const cholmod_sparse& A, cholmod_factor& L, const Int* only, size_t count,
                  bool order_lists, std::vector<Int>& head, Workspace& work);

  static constexpr int32_t kAll = -2, kTop = -1;
  std::vector<Int> owner_;          // column -> its supernode
  std::vector<int32_t> task_;       // supernode -> its subtree's task, kTop, or kAll (one thread)
  std::vector<size_t> task_start_;  // the tasks' supernodes, in order: task t's from start[t]
  std::vector<Int> task_members_, top_, every_;  // every_: 0 .. nsuper - 1, one thread's order
  std::vector<Int> own_below_;            // subtree supernode -> its rows below in its subtree
  std::vector<size_t> top_update_start_;  // task -> its first place in top_updates_
  std::vector<float> top_updates_;        // the subtrees' updates to the top part's rows
  size_t max_rows_ = 0, max_update_ = 0;
  double total_flops_ = 0.0;
  bool two_threads_ = false;
  std::atomic<size_t> factorized_{0};
  std::vector<Int> next_, lpos_;
  std::vector<Linked> linked_;
  Workspace work_[2];
  bool single_ = false;
  float* single_values_ = nullptr;  // SuiteSparse_malloc'ed, single_size_ floats
  size_t single_size_ = 0;
  std::vector<float> single_x_;  // a solve's right-hand side in floats
  std::vector<double> refined_;  // b, then the residual b - A x
  std::vector<double>
      spilled_;  // A x's terms from the first half of the columns in the second's rows
};

}  // namespace hydra_multi
