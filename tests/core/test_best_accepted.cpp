#include <gtest/gtest.h>

#include <random>

#include "hydra_multi/core/best_accepted.h"

namespace hydra_multi {
namespace {

// What a full pass testing every candidate gives: the lowest index of the highest score that
// both tests admit.
std::optional<size_t> fullPass(const std::vector<double>& score, const std::vector<bool>& ranked,
                               const std::vector<bool>& accepted) {
  std::optional<size_t> best;
  for (size_t k = 0; k < score.size(); ++k) {
    if (ranked[k] && accepted[k] && (!best || score[k] > score[*best])) best = k;
  }
  return best;
}

TEST(BestAccepted, AsAFullPassWithFewerTests) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> level(0, 6);  // few levels: many ties
  std::bernoulli_distribution coin(0.6);
  size_t tested = 0, fell_back = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const size_t n = static_cast<size_t>(trial % 40);
    std::vector<double> score(n);
    std::vector<bool> ranked(n), accepted(n);
    for (size_t k = 0; k < n; ++k) {
      score[k] = 0.1 * level(rng);
      ranked[k] = coin(rng);
      accepted[k] = coin(rng);
    }
    size_t tests = 0;
    const auto found = bestAccepted(
        score, [&](size_t k) { return bool(ranked[k]); },
        [&](size_t k) {
          EXPECT_TRUE(ranked[k]) << "tested a candidate not ranked";
          ++tests;
          return bool(accepted[k]);
        });
    EXPECT_EQ(found, fullPass(score, ranked, accepted)) << "trial " << trial;
    tested += tests;
    fell_back += tests > 1;
  }
  EXPECT_GT(fell_back, 50u);  // the heap's path is exercised
  EXPECT_LT(tested, 500u * 20u / 2u);
}

TEST(BestAccepted, TiesGoToTheLowerIndexOnBothPaths) {
  const std::vector<double> score = {0.5, 0.9, 0.9, 0.9, 0.2};
  const auto all = [](size_t) { return true; };
  EXPECT_EQ(bestAccepted(score, all, all), 1u);
  EXPECT_EQ(bestAccepted(score, all, [](size_t k) { return k != 1; }), 2u);
  EXPECT_EQ(bestAccepted(score, all, [](size_t k) { return k == 4 || k == 3; }), 3u);
  EXPECT_EQ(bestAccepted(
                score, [](size_t k) { return k != 1; }, all),
            2u);
  EXPECT_EQ(bestAccepted(score, all, [](size_t) { return false; }), std::nullopt);
  EXPECT_EQ(bestAccepted({}, all, all), std::nullopt);
}

}  // namespace
}  // namespace hydra_multi
