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
    Set all(words_, 0);
    for (size_t i = 0; i < n_; ++i) all[i / 64] |= uint64_t{1} << (i % 64);
    std::vector<size_t> current;
    expand(current, all);
    CliqueResult result;
    result.members = best_;
    std::sort(result.members.begin(), result.members.end());
    result.exhausted = steps_ <= max_steps_;
    return result;
  }

 private:
  // A set of vertices as a bit mask (words_ words); its members are visited in increasing order.
  using Set = std::vector<uint64_t>;

  void set(size_t i, size_t j) { bits_[i * words_ + j / 64] |= uint64_t{1} << (j % 64); }
  bool adjacent(size_t i, size_t j) const { return (bits_[i * words_ + j / 64] >> (j % 64)) & 1u; }
  static size_t count(const Set& s) {
    size_t n = 0;
    for (const uint64_t w : s) n += static_cast<size_t>(__builtin_popcountll(w));
    return n;
  }
  // The members of `s` adjacent to u.
  size_t degree(size_t u, const Set& s) const {
    size_t n = 0;
    for (size_t w = 0; w < words_; ++w)
      n += static_cast<size_t>(__builtin_popcountll(bits_[u * words_ + w] & s[w]));
    return n;
  }
  template <typename Visit>
  static void forEach(const Set& s, Visit visit) {
    for (size_t w = 0; w < s.size(); ++w) {
      for (uint64_t bits = s[w]; bits != 0; bits &= bits - 1)
        visit(w * 64 + static_cast<size_t>(__builtin_ctzll(bits)));
    }
  }

  void expand(std::vector<size_t>& clique, const Set& candidates) {
    if (++steps_ > max_steps_) return;
    const size_t size = count(candidates);
    if (size == 0) {
      if (clique.size() > best_.size()) best_ = clique;
      return;
    }
    if (clique.size() + size <= best_.size()) return;  // cannot win
    // Pivot: the candidate with the most neighbours among the candidates (the first of those).
    size_t pivot = n_, pivot_degree = 0;
    forEach(candidates, [&](size_t u) {
      const size_t d = degree(u, candidates);
      if (pivot == n_ || d > pivot_degree) {
        pivot = u;
        pivot_degree = d;
      }
    });
    Set remaining = candidates;
    size_t remaining_size = size;
    Set next(words_);
    for (size_t w = 0; w < words_; ++w) {
      for (uint64_t bits = candidates[w]; bits != 0; bits &= bits - 1) {
        const size_t v = w * 64 + static_cast<size_t>(__builtin_ctzll(bits));
        if (v != pivot && adjacent(pivot, v)) continue;
        if (clique.size() + remaining_size <= best_.size()) return;
        for (size_t x = 0; x < words_; ++x) next[x] = remaining[x] & bits_[v * words_ + x];
        clique.push_back(v);
        expand(clique, next);
        clique.pop_back();
        remaining[v / 64] &= ~(uint64_t{1} << (v % 64));
        --remaining_size;
        if (steps_ > max_steps_) return;
      }
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
