#pragma once
// Chordal initialization (Carlone et al., ICRA 2015, "Initialization techniques for 3D SLAM").
//
// Rotations: relax R_i in SO(3) to any 3x3 matrix and minimize sum kappa_ij ||R_j - R_i R_ij||_F^2
// with R_anchor = I. Row k of the residual is y_j - R_ij^T y_i with y_i = R_i^T e_k, so the problem
// splits into three linear least-squares problems that share one sparse matrix (one
// factorization, three right-hand sides). Each estimate is then projected to SO(3).
// Translations: with the rotations fixed, minimize sum tau_ij ||t_j - t_i - R_i t_ij||^2 with
// t_anchor = 0: again one scalar Laplacian system per coordinate.

#include <functional>
#include <map>

#include "hydra_multi/core/result.h"
#include "hydra_multi/optim/pose_graph.h"

namespace hydra_multi {

/// Which edges to use (e.g. only known inliers when outliers may be present); all when empty.
using EdgeFilter = std::function<bool(const PoseGraphEdge&)>;

/// Poses of every node joined to the anchor by the used edges; fails when the anchor has no edge.
/// Nodes not joined to the anchor are left out of the result.
Result<std::map<NodeId, Eigen::Isometry3d>> chordalInitialization(const PoseGraph& graph,
                                                                  NodeId anchor,
                                                                  const EdgeFilter& use_edge = {});

}  // namespace hydra_multi
