#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "hydra_multi/optim/sparse_lm_impl.h"

namespace hydra_multi {
namespace {

using sparse_lm::Block;
using sparse_lm::Vector6;

// A random symmetric positive definite block: Q diag(lambda) Q^T with eigenvalues from `low` to
// `high`, as the damped diagonal blocks of H range.
Block randomPositiveDefinite(std::mt19937& rng, double low, double high) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  Block M;
  for (int c = 0; c < 6; ++c) {
    for (int r = 0; r < 6; ++r) M(r, c) = gauss(rng);
  }
  const Eigen::HouseholderQR<Block> qr(M);
  const Block Q = qr.householderQ();
  Vector6 lambda;
  for (int k = 0; k < 6; ++k) lambda[k] = low * std::pow(high / low, k / 5.0);
  const Block D = Q * lambda.asDiagonal() * Q.transpose();
  return Block((D + D.transpose()) / 2);
}

// An eliminated pose's diagonal block is factored as D = L L^T, L lower triangular, and the two
// substitutions with L solve D x = b as a general solver does, within the block's conditioning.
TEST(SparseLmBlocks, APositiveDefiniteBlockIsFactoredAndSolved) {
  std::mt19937 rng(91);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (const auto& [low, high] : {std::pair{1.0, 10.0}, {1e-6, 1e4}, {1e2, 1e8}}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Block D = randomPositiveDefinite(rng, low, high);
      Block L;
      L.setConstant(7.0);  // whatever was there before
      ASSERT_TRUE(sparse_lm::choleskyFactor(D, L));
      EXPECT_TRUE(L.triangularView<Eigen::StrictlyUpper>().toDenseMatrix().isZero(0.0));
      EXPECT_LT((L * L.transpose() - D).norm(), 1e-14 * D.norm()) << low << " " << high;
      Vector6 b;
      for (int k = 0; k < 6; ++k) b[k] = gauss(rng);
      Vector6 x = b;
      sparse_lm::solveLower(L, x);
      EXPECT_LT((L * x - b).norm(), 1e-12 * b.norm() * std::sqrt(high / low));
      sparse_lm::solveLowerTransposed(L, x);
      const Vector6 general = D.fullPivLu().solve(b);
      EXPECT_LT((x - general).norm(), 1e-14 * (high / low) * general.norm());
    }
  }
}

// B L^-T, taken column by column, is each row of B through solveLower, to the bit.
TEST(SparseLmBlocks, ABlockOfRowsIsSolvedAsEachRowAlone) {
  std::mt19937 rng(93);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (const auto& [low, high] : {std::pair{1.0, 10.0}, {1e-6, 1e4}}) {
    const Block D = randomPositiveDefinite(rng, low, high);
    Block L;
    ASSERT_TRUE(sparse_lm::choleskyFactor(D, L));
    Block B;
    for (int c = 0; c < 6; ++c) {
      for (int r = 0; r < 6; ++r) B(r, c) = gauss(rng);
    }
    Block Y = B;
    sparse_lm::solveRightLowerTransposed(L, Y);
    for (int row = 0; row < 6; ++row) {
      Vector6 y = B.row(row).transpose();
      sparse_lm::solveLower(L, y);
      EXPECT_TRUE(Y.row(row) == y.transpose()) << row;
    }
    EXPECT_LT((Y * L.transpose() - B).norm(), 1e-12 * B.norm() * std::sqrt(high / low));
  }
}

// Only the lower triangle is read: an upper triangle left unset does not change the factor.
TEST(SparseLmBlocks, OnlyTheLowerTriangleIsRead) {
  std::mt19937 rng(92);
  const Block D = randomPositiveDefinite(rng, 0.5, 50.0);
  Block lower = D;
  lower.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);
  Block from_full, from_lower;
  ASSERT_TRUE(sparse_lm::choleskyFactor(D, from_full));
  ASSERT_TRUE(sparse_lm::choleskyFactor(lower, from_lower));
  EXPECT_EQ(from_full, from_lower);
}

// A block that is not positive definite (a negative eigenvalue, zero, not a number) is refused,
// as the step that needs it then is.
TEST(SparseLmBlocks, ABlockThatIsNotPositiveDefiniteIsRefused) {
  std::mt19937 rng(93);
  const Block D = randomPositiveDefinite(rng, 1.0, 10.0);
  const Vector6 v = Vector6::Ones().normalized();
  Block L;
  // D - 20 v v^T, v a unit vector: an eigenvalue below 10 - 20 < 0.
  EXPECT_FALSE(sparse_lm::choleskyFactor(Block(D - 20.0 * v * v.transpose()), L));
  EXPECT_FALSE(sparse_lm::choleskyFactor(Block::Zero(), L));
  Block nan = D;
  nan(3, 2) = std::numeric_limits<double>::quiet_NaN();
  nan(2, 3) = nan(3, 2);
  EXPECT_FALSE(sparse_lm::choleskyFactor(nan, L));
  Block nan_pivot = D;
  nan_pivot(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(sparse_lm::choleskyFactor(nan_pivot, L));
}

}  // namespace
}  // namespace hydra_multi
