#pragma once
// Maximum clique of an undirected graph, exact by branch and bound (Bron-Kerbosch with a pivot,
// pruning branches that cannot beat the best clique found), as TEASER++ uses to keep the mutually
// consistent correspondences. Consistency graphs of registration are sparse but for the inliers,
// so the search is fast; `max_steps` bounds it, and when it is hit the best clique found so far
// is returned (and `exhausted` is false).

#include <cstddef>
#include <vector>

namespace hydra_multi {

struct CliqueResult {
  std::vector<size_t> members;  ///< increasing
  bool exhausted = true;        ///< false when max_steps stopped the search early
};

/// `adjacency[i]` lists the neighbours of vertex i (symmetric, no self loops).
CliqueResult maximumClique(const std::vector<std::vector<size_t>>& adjacency,
                           size_t max_steps = 1000000);

}  // namespace hydra_multi
