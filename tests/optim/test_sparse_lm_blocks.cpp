#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "hydra_multi/optim/sparse_lm_impl.h"

namespace hydra_multi {
namespace {

using sparse_lm::Block;
using sparse_lm::inverseOfPositiveDefinite;

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
  Eigen::Matrix<double, 6, 1> lambda;
  for (int k = 0; k < 6; ++k) lambda[k] = low * std::pow(high / low, k / 5.0);
  const Block D = Q * lambda.asDiagonal() * Q.transpose();
  return Block((D + D.transpose()) / 2);
}

// An eliminated pose's diagonal block is inverted through its Cholesky factor: the inverse is
// exactly symmetric and, within the block's conditioning, what a general inverse gives.
TEST(SparseLmBlocks, APositiveDefiniteBlockIsInvertedSymmetrically) {
  std::mt19937 rng(91);
  for (const auto& [low, high] : {std::pair{1.0, 10.0}, {1e-6, 1e4}, {1e2, 1e8}}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Block D = randomPositiveDefinite(rng, low, high);
      Block inverse;
      ASSERT_TRUE(inverseOfPositiveDefinite(D, inverse));
      EXPECT_EQ(inverse, inverse.transpose());
      const double condition = high / low;
      const Block product = D * inverse;
      EXPECT_LT((product - Block::Identity()).norm(), 1e-14 * condition) << low << " " << high;
      const Block general = D.inverse();
      EXPECT_LT((inverse - general).norm(), 1e-14 * condition * general.norm());
    }
  }
}

// Only the lower triangle is read: an upper triangle left unset does not change the inverse.
TEST(SparseLmBlocks, OnlyTheLowerTriangleIsRead) {
  std::mt19937 rng(92);
  const Block D = randomPositiveDefinite(rng, 0.5, 50.0);
  Block lower = D;
  lower.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);
  Block from_full, from_lower;
  ASSERT_TRUE(inverseOfPositiveDefinite(D, from_full));
  ASSERT_TRUE(inverseOfPositiveDefinite(lower, from_lower));
  EXPECT_EQ(from_full, from_lower);
}

// A block that is not positive definite (a negative eigenvalue, zero, not a number) is refused,
// as the step that needs it then is.
TEST(SparseLmBlocks, ABlockThatIsNotPositiveDefiniteIsRefused) {
  std::mt19937 rng(93);
  const Block D = randomPositiveDefinite(rng, 1.0, 10.0);
  const Eigen::Matrix<double, 6, 1> v = Eigen::Matrix<double, 6, 1>::Ones().normalized();
  Block inverse;
  // D - 20 v v^T, v a unit vector: an eigenvalue below 10 - 20 < 0.
  EXPECT_FALSE(inverseOfPositiveDefinite(Block(D - 20.0 * v * v.transpose()), inverse));
  EXPECT_FALSE(inverseOfPositiveDefinite(Block::Zero(), inverse));
  Block nan = D;
  nan(3, 2) = std::numeric_limits<double>::quiet_NaN();
  nan(2, 3) = nan(3, 2);
  EXPECT_FALSE(inverseOfPositiveDefinite(nan, inverse));
  Block nan_pivot = D;
  nan_pivot(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(inverseOfPositiveDefinite(nan_pivot, inverse));
}

}  // namespace
}  // namespace hydra_multi
