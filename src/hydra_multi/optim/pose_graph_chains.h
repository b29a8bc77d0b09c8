#pragma once
// Series reduction of a pose graph. A chain is a path u - x_1 - ... - x_m - v whose interior poses
// x_k have exactly two edges, both known inliers (not loop closures) with a positive definite
// information; u and v are any other poses (the same one for a loop). The chain's edges compose to
// one edge u -> v:
//   Z = Z_1 Z_2 ... Z_m,   Sigma = sum_k A_k Sigma_k A_k^T,   A_k = Ad(Z_{k+1} ... Z_m)^-1,
// with each Z_k oriented along the chain and its noise on the right (T_i^-1 T_j = Z exp(n), the
// geodesic residual's convention, residuals.h), so that to first order the composed edge's cost at
// given u and v is the chain's cost with its interior at its best. After a solve of the reduced
// graph the interior is placed where that first-order optimum puts it: with d = log(Z^-1 T_u^-1
// T_v) the chain's misfit, n_k = Sigma_k A_k^T Sigma^-1 d and T_{x_k} = T_u Z_1 exp(n_1) ... Z_k
// exp(n_k).

#include <map>
#include <set>
#include <vector>

#include "hydra_multi/optim/pose_graph.h"

namespace hydra_multi {

struct PoseGraphChain {
  NodeId from, to;               ///< u and v
  std::vector<size_t> edges;     ///< graph edges from u to v
  std::vector<bool> reversed;    ///< per edge: stored from its later pose to its earlier one
  std::vector<NodeId> interior;  ///< x_1 ... x_m
};

struct ChainReduction {
  std::vector<PoseGraphChain> chains;
  std::vector<PoseGraphEdge> composed;  ///< per chain, its edge u -> v (odometry)
  std::vector<size_t> kept_edges;       ///< the graph's edges in no chain
};

/// The chains of `graph` over the poses `initial` has (edges with a missing endpoint or from a pose
/// to itself count for nothing); `anchor` and `constant` are never interior. A cycle of interior
/// candidates alone keeps one of its poses. No chains: an empty reduction.
ChainReduction findChains(const PoseGraph& graph,
                          const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                          const std::set<NodeId>& constant = {});

/// Places every chain's interior in `poses` from its solved ends (see the header).
void placeChainInteriors(const PoseGraph& graph, const ChainReduction& reduction,
                         std::map<NodeId, Eigen::Isometry3d>& poses);

}  // namespace hydra_multi
