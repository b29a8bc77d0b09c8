#pragma once
// Maximum clique of an undirected graph, exact by branch and bound (Bron-Kerbosch with a pivot,
// pruning branches that cannot beat the best clique found), as TEASER++ uses to keep the mutually
// consistent correspondences. Consistency graphs of registration are sparse but for the inliers,
// so the search is fast; `max_steps` bounds it, and when it is hit the best clique found so far
// is returned (and `exhausted` is false).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hydra_multi {

struct CliqueResult {
  std::vector<size_t> members;  ///< increasing
  bool exhausted = true;        ///< false when max_steps stopped the search early
};

/// An undirected graph of n vertices as bit rows: bit j of row i set where i and j are adjacent.
class AdjacencyBits {
 public:
  explicit AdjacencyBits(size_t n) : n_(n), words_((n + 63) / 64), bits_(n_ * words_, 0) {}
  /// i and j adjacent, both ways (a self loop is ignored).
  void connect(size_t i, size_t j) {
    if (i == j) return;
    bits_[i * words_ + j / 64] |= uint64_t{1} << (j % 64);
    bits_[j * words_ + i / 64] |= uint64_t{1} << (i % 64);
  }
  size_t size() const { return n_; }
  size_t words() const { return words_; }  ///< per row
  const uint64_t* row(size_t i) const { return &bits_[i * words_]; }

 private:
  size_t n_, words_;
  std::vector<uint64_t> bits_;
};

CliqueResult maximumClique(const AdjacencyBits& adjacency, size_t max_steps = 1000000);

}  // namespace hydra_multi
