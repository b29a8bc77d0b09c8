#include "hydra_multi/registration/max_clique.h"

#include <algorithm>
#include <cstdint>

namespace hydra_multi {
namespace {

// The set bits of w, inline (SWAR): __builtin_popcountll is a library call on a baseline x86-64
// build, and the pivot's choice counts bits for every candidate.
inline size_t bitCount(uint64_t w) {
  w -= (w >> 1) & 0x5555555555555555ull;
  w = (w & 0x3333333333333333ull) + ((w >> 2) & 0x3333333333333333ull);
  w = (w + (w >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return static_cast<size_t>((w * 0x0101010101010101ull) >> 56);
}

class CliqueSearch {
 public:
  CliqueSearch(const AdjacencyBits& adjacency, size_t max_steps)
      : max_steps_(max_steps), n_(adjacency.size()), words_(adjacency.words()), bits_(adjacency) {}

  CliqueResult run() {
    // Per depth of the search, its remaining candidates and its child's: (2 n + 3) sets, the
    // first all vertices.
    sets_.assign((2 * n_ + 3) * words_, 0);
    for (size_t i = 0; i < n_; ++i) sets_[i / 64] |= uint64_t{1} << (i % 64);
    std::vector<size_t> current;
    expand(current, sets_.data());
    CliqueResult result;
    result.members = best_;
    std::sort(result.members.begin(), result.members.end());
    result.exhausted = steps_ <= max_steps_;
    return result;
  }

 private:
  // A set of vertices is a bit mask of words_ words; its members are visited in increasing order.
  bool adjacent(size_t i, size_t j) const { return (bits_.row(i)[j / 64] >> (j % 64)) & 1u; }
  size_t count(const uint64_t* s) const {
    size_t n = 0;
    for (size_t w = 0; w < words_; ++w) n += bitCount(s[w]);
    return n;
  }
  // The members of `s` adjacent to u.
  size_t degree(size_t u, const uint64_t* s) const {
    size_t n = 0;
    for (size_t w = 0; w < words_; ++w) n += bitCount(bits_.row(u)[w] & s[w]);
    return n;
  }
  template <typename Visit>
  void forEach(const uint64_t* s, Visit visit) const {
    for (size_t w = 0; w < words_; ++w) {
      for (uint64_t bits = s[w]; bits != 0; bits &= bits - 1)
        visit(w * 64 + static_cast<size_t>(__builtin_ctzll(bits)));
    }
  }

  void expand(std::vector<size_t>& clique, const uint64_t* candidates) {
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
    uint64_t* remaining = &sets_[(2 * clique.size() + 1) * words_];
    uint64_t* next = remaining + words_;
    std::copy(candidates, candidates + words_, remaining);
    size_t remaining_size = size;
    for (size_t w = 0; w < words_; ++w) {
      for (uint64_t bits = candidates[w]; bits != 0; bits &= bits - 1) {
        const size_t v = w * 64 + static_cast<size_t>(__builtin_ctzll(bits));
        if (v != pivot && adjacent(pivot, v)) continue;
        if (clique.size() + remaining_size <= best_.size()) return;
        for (size_t x = 0; x < words_; ++x) next[x] = remaining[x] & bits_.row(v)[x];
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
  const AdjacencyBits& bits_;
  std::vector<uint64_t> sets_;
  std::vector<size_t> best_;
};

}  // namespace

CliqueResult maximumClique(const AdjacencyBits& adjacency, size_t max_steps) {
  return CliqueSearch(adjacency, max_steps).run();
}

}  // namespace hydra_multi
