#include "hydra_multi/registration/max_clique.h"

#include <algorithm>
#include <cstdint>

namespace hydra_multi {
namespace {

class CliqueSearch {
 public:
  CliqueSearch(const std::vector<std::vector<size_t>>& adjacency, size_t max_steps)
      : max_steps_(max_steps), n_(adjacency.size()), words_((n_ + 63) / 64) {
    bits_.assign(n_ * words_, 0);
    for (size_t i = 0; i < n_; ++i) {
      for (const size_t j : adjacency[i]) {
        if (j < n_ && j != i) {
          set(i, j);
          set(j, i);
        }
      }
    }
  }

  CliqueResult run() {
    std::vector<size_t> all(n_);
    for (size_t i = 0; i < n_; ++i) all[i] = i;
    std::vector<size_t> current;
    expand(current, all);
    CliqueResult result;
    result.members = best_;
    std::sort(result.members.begin(), result.members.end());
    result.exhausted = steps_ <= max_steps_;
    return result;
  }

 private:
  void set(size_t i, size_t j) { bits_[i * words_ + j / 64] |= uint64_t{1} << (j % 64); }
  bool adjacent(size_t i, size_t j) const { return (bits_[i * words_ + j / 64] >> (j % 64)) & 1u; }

  void expand(std::vector<size_t>& clique, std::vector<size_t> candidates) {
    if (++steps_ > max_steps_) return;
    if (candidates.empty()) {
      if (clique.size() > best_.size()) best_ = clique;
      return;
    }
    if (clique.size() + candidates.size() <= best_.size()) return;  // cannot win
    // Pivot: the candidate with the most neighbours among the candidates.
    size_t pivot = candidates.front(), pivot_degree = 0;
    for (const size_t u : candidates) {
      size_t degree = 0;
      for (const size_t v : candidates) degree += adjacent(u, v);
      if (degree > pivot_degree || (degree == pivot_degree && u < pivot)) {
        pivot = u;
        pivot_degree = degree;
      }
    }
    std::vector<size_t> remaining = candidates;
    for (const size_t v : candidates) {
      if (v != pivot && adjacent(pivot, v)) continue;
      if (clique.size() + remaining.size() <= best_.size()) return;
      std::vector<size_t> next;
      for (const size_t w : remaining) {
        if (adjacent(v, w)) next.push_back(w);
      }
      clique.push_back(v);
      expand(clique, std::move(next));
      clique.pop_back();
      remaining.erase(std::find(remaining.begin(), remaining.end(), v));
      if (steps_ > max_steps_) return;
    }
  }

  size_t max_steps_, steps_ = 0;
  size_t n_, words_;
  std::vector<uint64_t> bits_;
  std::vector<size_t> best_;
};

}  // namespace

CliqueResult maximumClique(const std::vector<std::vector<size_t>>& adjacency, size_t max_steps) {
  return CliqueSearch(adjacency, max_steps).run();
}

}  // namespace hydra_multi
