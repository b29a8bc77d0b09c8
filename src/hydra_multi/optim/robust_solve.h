#pragma once
// The robust solve inside optimizePoseGraph (robust_pose_graph.h), on a graph whose leaves (and,
// where reduced, chains) are out: GNC-TLS over the undecided loop closures from the problem's
// poses, then the polish (the exact optimum over the inliers, the rejected loop closures that fit
// it taken back and solved in), and the known inliers its result contradicts decided again.
// Internal to optim.

#include <map>
#include <string>
#include <vector>

#include "hydra_multi/optim/robust_pose_graph.h"

namespace hydra_multi {
namespace robust_pgo {

// Per edge of the graph a solve sees: the factors GNC holds out and those known to be inliers
// (RobustPgoOptions::held_out and known_inlier; shorter: the rest are neither).
struct EdgeFlags {
  std::vector<bool> held_out, known_inlier;
  bool heldOut(size_t k) const { return k < held_out.size() && held_out[k]; }
  bool known(size_t k) const { return k < known_inlier.size() && known_inlier[k]; }
};

// "<s> s", for the progress lines.
std::string seconds(double s);

// One solve, from `poses`, of a problem made of the edges of `graph` that `inlier` says (the
// options' constant poses held); `poses` becomes its solution.
SolveSummary solveOverInliers(const PoseGraph& graph, const std::vector<bool>& inlier,
                              std::map<NodeId, Eigen::Isometry3d>& poses, NodeId anchor,
                              const RobustPgoOptions& options);

// The solve of optimizePoseGraph without leaves (their poses absent from `initial`, which leaves
// their edges out) and without chains, when reduced; `flags` per edge of `graph`.
RobustPgoResult optimizeReduced(const PoseGraph& graph,
                                const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                                const RobustPgoOptions& options, const EdgeFlags& flags);

}  // namespace robust_pgo
}  // namespace hydra_multi
