#include "hydra_multi/optim/supernodal_cholesky.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "hydra_multi/optim/fill_reducing_ordering.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/sparse_lm_impl.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

// ||a - b|| / ||b||.
template <typename T>
double relativeError(const std::vector<T>& a, const std::vector<double>& b) {
  double error = 0.0, norm = 0.0;
  for (size_t k = 0; k < b.size(); ++k) {
    error += (a[k] - b[k]) * (a[k] - b[k]);
    norm += b[k] * b[k];
  }
  return std::sqrt(error / norm);
}

// A symmetric positive definite matrix of 6x6 blocks on the pattern of a real pose graph
// (sphere2500: 2,500 poses; copies() of it, not joined), each edge adding w [I -I; -I I] (w
// random), each pose w I; stored as its lower triangle in a fill-reducing order
// (fill_reducing_ordering.h), analyzed supernodally in that order as the solver's analysis does.
class SupernodalCholeskyTest : public ::testing::Test {
 protected:
  virtual int copies() const { return 1; }

  void SetUp() override {
    cholmod_l_start(&common_);
    auto g2o = io::readG2o(testing::dataDir() + "/pgo/sphere2500.g2o");
    ASSERT_TRUE(g2o.ok()) << g2o.error();
    std::map<NodeId, long> index;
    for (const auto& [id, pose] : g2o.value().graph.poses)
      index.emplace(id, static_cast<long>(index.size()));
    const long graph_poses = static_cast<long>(index.size());
    const long poses = copies() * graph_poses;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> weight(1.0, 10.0);
    // Per block (row >= column, in pose numbers), its weight times I.
    std::map<std::pair<long, long>, double> blocks;
    for (long p = 0; p < poses; ++p) blocks[{p, p}] += weight(random);
    for (long copy = 0; copy < copies(); ++copy) {
      for (const PoseGraphEdge& e : g2o.value().graph.edges) {
        const long a = copy * graph_poses + index.at(e.from);
        const long b = copy * graph_poses + index.at(e.to);
        if (a == b) continue;
        const double w = weight(random);
        blocks[{a, a}] += w;
        blocks[{b, b}] += w;
        blocks[{std::max(a, b), std::min(a, b)}] -= w;
      }
    }
    std::vector<std::vector<long>> rows(poses);
    for (const auto& [rc, w] : blocks) rows[rc.first].push_back(rc.second);
    for (auto& column : rows) std::sort(column.begin(), column.end());
    const auto ordering = orderForCholesky(rows, 0);
    ASSERT_TRUE(ordering.has_value());
    std::vector<long> place(poses);
    for (long k = 0; k < poses; ++k) place[ordering->column[k]] = k;
    // Lower triangle, in the new order, column by column.
    std::vector<std::map<long, double>> columns(6 * poses);
    for (const auto& [rc, w] : blocks) {
      const long r = std::max(place[rc.first], place[rc.second]);
      const long c = std::min(place[rc.first], place[rc.second]);
      for (int i = 0; i < 6; ++i) {
        const long row = 6 * r + i;
        for (int j = 0; j < 6; ++j) {
          const long col = 6 * c + j;
          if (row < col) continue;
          double value = i == j ? w : 0.0;
          if (r == c && i == j) value += 0.01 * (i + 1);  // distinct diagonal entries
          columns[col][row] = value;
        }
      }
    }
    size_t entries = 0;
    for (const auto& column : columns) entries += column.size();
    A_ = cholmod_l_allocate_sparse(6 * poses, 6 * poses, entries, 1, 1, -1, CHOLMOD_REAL, &common_);
    ASSERT_NE(A_, nullptr);
    auto* p = static_cast<SuiteSparse_long*>(A_->p);
    auto* i = static_cast<SuiteSparse_long*>(A_->i);
    auto* x = static_cast<double*>(A_->x);
    long at = 0;
    for (size_t c = 0; c < columns.size(); ++c) {
      p[c] = at;
      for (const auto& [row, value] : columns[c]) {
        i[at] = row;
        x[at++] = value;
      }
    }
    p[columns.size()] = at;
    common_.nrelax[0] = 8;
    common_.nrelax[1] = 32;
    common_.nrelax[2] = 256;
    common_.supernodal = CHOLMOD_SUPERNODAL;
    common_.final_asis = 1;
    common_.postorder = 0;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_NATURAL;
    L_ = cholmod_l_analyze(A_, &common_);
    ASSERT_NE(L_, nullptr);
    ASSERT_TRUE(L_->is_super);
  }

  void TearDown() override {
    if (L_ != nullptr) cholmod_l_free_factor(&L_, &common_);
    if (A_ != nullptr) cholmod_l_free_sparse(&A_, &common_);
    cholmod_l_finish(&common_);
  }

  // The factor's lower parts (the diagonal blocks' upper triangles are not part of it); floats:
  // a factor in single precision.
  template <typename T = double>
  std::vector<T> lower(const T* x = nullptr) const {
    const auto* super = static_cast<const SuiteSparse_long*>(L_->super);
    const auto* pi = static_cast<const SuiteSparse_long*>(L_->pi);
    const auto* px = static_cast<const SuiteSparse_long*>(L_->px);
    if (x == nullptr) x = static_cast<const T*>(L_->x);
    std::vector<T> values;
    for (size_t s = 0; s < L_->nsuper; ++s) {
      const long columns = super[s + 1] - super[s], height = pi[s + 1] - pi[s];
      for (long j = 0; j < columns; ++j)
        values.insert(values.end(), x + px[s] + j * height + j, x + px[s] + (j + 1) * height);
    }
    return values;
  }

  // A right-hand side of normal values (seed 11), and CHOLMOD's solution of A x = b with L_ as
  // factorized.
  std::vector<double> rightHandSide() const {
    std::mt19937 random(11);
    std::normal_distribution<double> value(0.0, 1.0);
    std::vector<double> b(A_->nrow);
    for (double& v : b) v = value(random);
    return b;
  }
  std::vector<double> cholmodSolution(const std::vector<double>& rhs) {
    cholmod_dense* b = cholmod_l_zeros(A_->nrow, 1, CHOLMOD_REAL, &common_);
    EXPECT_NE(b, nullptr);
    std::copy(rhs.begin(), rhs.end(), static_cast<double*>(b->x));
    cholmod_dense* x = cholmod_l_solve(CHOLMOD_A, L_, b, &common_);
    EXPECT_NE(x, nullptr);
    std::vector<double> solution(static_cast<const double*>(x->x),
                                 static_cast<const double*>(x->x) + A_->nrow);
    cholmod_l_free_dense(&x, &common_);
    cholmod_l_free_dense(&b, &common_);
    return solution;
  }

  // Our factor is CHOLMOD's to the bit on one thread and `runs` times on two.
  void factorIsCholmods(int runs) {
    ASSERT_TRUE(cholmod_l_factorize(A_, L_, &common_));
    ASSERT_EQ(common_.status, CHOLMOD_OK);
    const std::vector<double> cholmod = lower();
    SupernodalCholesky ours(*L_);
    ASSERT_TRUE(ours.splits()) << ours.flops() << " flops";
    for (const int threads : {1, 2}) {
      for (int run = 0; run < (threads == 1 ? 1 : runs); ++run) {
        std::memset(L_->x, 0, sizeof(double) * L_->xsize);
        ASSERT_TRUE(ours.factorize(*A_, *L_, threads));
        EXPECT_EQ(ours.factorized(), L_->nsuper) << threads << " thread(s): each supernode once";
        const std::vector<double> factor = lower();
        ASSERT_EQ(factor.size(), cholmod.size());
        EXPECT_EQ(std::memcmp(factor.data(), cholmod.data(), sizeof(double) * factor.size()), 0)
            << threads << " thread(s), run " << run;
      }
    }
  }

  // Our solution is CHOLMOD's to the bit on one thread and `runs` times on two.
  void solutionIsCholmods(int runs) {
    SupernodalCholesky ours(*L_);
    ASSERT_TRUE(cholmod_l_factorize(A_, L_, &common_));  // L's values allocated
    ASSERT_TRUE(ours.factorize(*A_, *L_, 2));
    ASSERT_TRUE(ours.splits());
    const std::vector<double> rhs = rightHandSide();
    const std::vector<double> cholmod = cholmodSolution(rhs);
    for (const int threads : {1, 2}) {
      for (int run = 0; run < (threads == 1 ? 1 : runs); ++run) {
        std::vector<double> solution = rhs;
        ours.solve(*L_, solution.data(), threads);
        EXPECT_EQ(std::memcmp(solution.data(), cholmod.data(), sizeof(double) * solution.size()), 0)
            << threads << " thread(s), run " << run;
      }
    }
  }

  // In single precision: the same factor, solution and refined solution to the bit on one thread
  // and `runs` times on two, the factor within single precision's error of CHOLMOD's, the solve
  // refined once in double within 1e-12 of CHOLMOD's solution where the floats' own is within
  // 1e-5 and not within 1e-8.
  void singlePrecisionIsCholmodsWithinItsError(int runs) {
    ASSERT_TRUE(cholmod_l_factorize(A_, L_, &common_));
    ASSERT_EQ(common_.status, CHOLMOD_OK);
    const std::vector<double> cholmod = lower();
    const std::vector<double> rhs = rightHandSide();
    const std::vector<double> exact = cholmodSolution(rhs);
    SupernodalCholesky ours(*L_);
    ASSERT_TRUE(ours.splits());
    std::vector<float> first;
    std::vector<double> first_solution, first_unrefined;
    for (const int threads : {1, 2}) {
      for (int run = 0; run < (threads == 1 ? 1 : runs); ++run) {
        ASSERT_TRUE(ours.factorize(*A_, *L_, threads, true));
        EXPECT_TRUE(ours.single());
        EXPECT_EQ(ours.factorized(), L_->nsuper);
        const std::vector<float> factor = lower(ours.singleValues());
        ASSERT_EQ(factor.size(), cholmod.size());
        if (first.empty()) {
          first = factor;
          EXPECT_LT(relativeError(factor, cholmod), 1e-6);
          EXPECT_GT(relativeError(factor, cholmod), 0.0) << "computed in floats";
        }
        EXPECT_EQ(std::memcmp(factor.data(), first.data(), sizeof(float) * factor.size()), 0)
            << threads << " thread(s), run " << run;
        std::vector<double> unrefined = rhs, refined = rhs;
        ours.solve(*L_, unrefined.data(), threads);
        ours.solve(*A_, *L_, refined.data(), threads);
        EXPECT_GT(relativeError(unrefined, exact), 1e-8);
        EXPECT_LT(relativeError(unrefined, exact), 1e-5);
        EXPECT_LT(relativeError(refined, exact), 1e-12) << threads << " thread(s), run " << run;
        if (first_solution.empty()) {
          first_solution = refined;
          first_unrefined = unrefined;
        }
        EXPECT_EQ(std::memcmp(unrefined.data(), first_unrefined.data(),
                              sizeof(double) * unrefined.size()),
                  0)
            << threads << " thread(s), run " << run;
        EXPECT_EQ(
            std::memcmp(refined.data(), first_solution.data(), sizeof(double) * refined.size()), 0)
            << threads << " thread(s), run " << run;
      }
    }
    const std::vector<double> untouched = lower();  // the floats are the object's own
    EXPECT_EQ(std::memcmp(untouched.data(), cholmod.data(), sizeof(double) * cholmod.size()), 0);
  }

  cholmod_common common_;
  cholmod_sparse* A_ = nullptr;
  cholmod_factor* L_ = nullptr;
};

// Two threads ten times: their dense calls overlap, each on its own buffer only while OpenBLAS's
// buffer allocation is serialized (without it this fails).
TEST_F(SupernodalCholeskyTest, TheFactorIsCholmodsToTheBitOnOneThreadAndOnTwo) {
  factorIsCholmods(10);
}

TEST_F(SupernodalCholeskyTest, TheSolutionIsCholmodsToTheBitOnOneThreadAndOnTwo) {
  solutionIsCholmods(10);
}

TEST_F(SupernodalCholeskyTest, InSinglePrecisionTheSameOnOneThreadAndOnTwoAndRefinedToDouble) {
  singlePrecisionIsCholmodsWithinItsError(5);
}

// Two copies of the pattern, not joined: the elimination tree is a forest, its two trees the
// subtrees of the cut, with no top part.
class SupernodalCholeskyForestTest : public SupernodalCholeskyTest {
 protected:
  int copies() const override { return 2; }
};

TEST_F(SupernodalCholeskyForestTest, TheFactorAndSolutionAreCholmodsToTheBit) {
  factorIsCholmods(3);
  solutionIsCholmods(3);
  singlePrecisionIsCholmodsWithinItsError(2);
}

// The solver's symbolic factor made from A's block pattern (sparse_lm::supernodalFromBlocks):
// CHOLMOD's counts of the scalar factor exactly, supernodes and a factor size within 1 % of
// CHOLMOD's analysis of the scalar pattern, and a factor on which the supernodal factorization
// solves A x = b as CHOLMOD does, within 1e-12 (the partition differs, so not to the bit).
TEST_F(SupernodalCholeskyTest, TheSymbolicFactorFromTheBlockPatternFactorizesA) {
  const double fl = common_.fl, lnz = common_.lnz;  // of the scalar analysis in SetUp
  ASSERT_TRUE(cholmod_l_factorize(A_, L_, &common_));
  const std::vector<double> rhs = rightHandSide();
  const std::vector<double> exact = cholmodSolution(rhs);
  const size_t blocks = A_->ncol / 6;
  std::vector<std::vector<long>> columns(blocks);  // block rows, from A's columns 6c
  const auto* p = static_cast<const SuiteSparse_long*>(A_->p);
  const auto* i = static_cast<const SuiteSparse_long*>(A_->i);
  for (size_t c = 0; c < blocks; ++c) {
    for (SuiteSparse_long q = p[6 * c]; q < p[6 * c + 1]; ++q) {
      if (columns[c].empty() || columns[c].back() != i[q] / 6) columns[c].push_back(i[q] / 6);
    }
  }
  double block_fl = 0.0, block_lnz = 0.0;  // the common's thresholds, as the solver passes them
  cholmod_factor* L =
      sparse_lm::supernodalFromBlocks(columns, common_.nrelax, common_, block_fl, block_lnz);
  ASSERT_NE(L, nullptr);
  EXPECT_EQ(common_.nrelax[0], 8u) << "the common's own thresholds kept";
  EXPECT_EQ(common_.supernodal, CHOLMOD_SUPERNODAL);
  EXPECT_EQ(block_fl, fl);
  EXPECT_EQ(block_lnz, lnz);
  EXPECT_TRUE(L->is_super);
  EXPECT_NEAR(double(L->nsuper), double(L_->nsuper), 0.01 * double(L_->nsuper));
  EXPECT_NEAR(double(L->xsize), double(L_->xsize), 0.01 * double(L_->xsize));
  ASSERT_TRUE(cholmod_l_change_factor(CHOLMOD_REAL, true, true, true, true, L, &common_));
  {
    SupernodalCholesky ours(*L);
    for (const int threads : {1, 2}) {
      ASSERT_TRUE(ours.factorize(*A_, *L, threads));
      std::vector<double> x = rhs;
      ours.solve(*L, x.data(), threads);
      EXPECT_LT(relativeError(x, exact), 1e-12) << threads << " thread(s)";
    }
  }
  cholmod_l_free_factor(&L, &common_);
}

TEST_F(SupernodalCholeskyTest, AMatrixNotPositiveDefiniteIsNotFactorized) {
  ASSERT_TRUE(cholmod_l_factorize(A_, L_, &common_));  // L's values allocated
  SupernodalCholesky ours(*L_);
  // A late column's diagonal entry made negative: its supernode's pivot fails, on one thread
  // or on two (then in the top part, or in a thread's subtrees).
  for (const long column : {6L * 1000 + 3, static_cast<long>(A_->ncol) - 1}) {
    auto* p = static_cast<SuiteSparse_long*>(A_->p);
    auto* x = static_cast<double*>(A_->x);
    const double kept = x[p[column]];  // the first entry of a lower column is its diagonal
    x[p[column]] = -1.0;
    for (const int threads : {1, 2}) {
      for (const bool single : {false, true}) {
        EXPECT_FALSE(ours.factorize(*A_, *L_, threads, single))
            << "column " << column << ", " << threads << ", single " << single;
      }
    }
    x[p[column]] = kept;
    EXPECT_TRUE(ours.factorize(*A_, *L_, 2));
  }
}

}  // namespace
}  // namespace hydra_multi
