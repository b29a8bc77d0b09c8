#pragma once
// The best of many candidates by score that a costlier test accepts, testing as few as possible:
// one pass finds the highest score among those `ranked` admits; when `accept` takes it (the usual
// case) that is all, otherwise the rest go on a heap and are tested best first. Ties go to the
// lower index, so the answer is the lowest index of the highest score that both admit, exactly as
// a full pass testing every candidate would give.

#include <algorithm>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace hydra_multi {

template <typename Ranked, typename Accept>
std::optional<size_t> bestAccepted(const std::vector<double>& score, Ranked ranked, Accept accept) {
  std::optional<size_t> best;
  for (size_t k = 0; k < score.size(); ++k) {
    if ((!best || score[k] > score[*best]) && ranked(k)) best = k;
  }
  if (!best || accept(*best)) return best;
  const auto worse = [](const std::pair<double, size_t>& a, const std::pair<double, size_t>& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::vector<std::pair<double, size_t>> heap;
  for (size_t k = 0; k < score.size(); ++k) {
    if (k != *best && ranked(k)) heap.emplace_back(score[k], k);
  }
  std::make_heap(heap.begin(), heap.end(), worse);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), worse);
    const size_t k = heap.back().second;
    heap.pop_back();
    if (accept(k)) return k;
  }
  return std::nullopt;
}

}  // namespace hydra_multi
