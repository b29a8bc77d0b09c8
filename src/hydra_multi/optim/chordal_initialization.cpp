#include "hydra_multi/optim/chordal_initialization.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <deque>
#include <unordered_map>
#include <unordered_set>

#include "hydra_multi/core/se3.h"
#include "hydra_multi/optim/residuals.h"

namespace hydra_multi {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

// The nodes joined to the anchor through the used edges, anchor first.
std::vector<NodeId> connectedNodes(const std::vector<const PoseGraphEdge*>& edges, NodeId anchor) {
  std::unordered_map<NodeId, std::vector<NodeId>> adjacency;
  for (const PoseGraphEdge* e : edges) {
    adjacency[e->from].push_back(e->to);
    adjacency[e->to].push_back(e->from);
  }
  std::vector<NodeId> order = {anchor};
  std::unordered_set<NodeId> seen = {anchor};
  for (size_t head = 0; head < order.size(); ++head) {
    for (const NodeId next : adjacency[order[head]]) {
      if (seen.insert(next).second) order.push_back(next);
    }
  }
  return order;
}

// Adds w * (x_j - M x_i - b)^2 terms to the normal equations H x = g over 3-blocks of unknowns;
// unknown index -1 is the anchor, whose value x_anchor moves to the right-hand side.
struct NormalEquations {
  explicit NormalEquations(size_t num_unknowns) : g(Eigen::MatrixXd::Zero(3 * num_unknowns, 3)) {}
  Triplets H;
  Eigen::MatrixXd g;  // three right-hand sides (one per row of the rotations, or per coordinate)

  void addBlock(long r, long c, const Eigen::Matrix3d& block) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        if (block(a, b) != 0.0) H.emplace_back(3 * r + a, 3 * c + b, block(a, b));
      }
    }
  }
  // Residual x_j - M x_i - b (b: 3x3, one column per right-hand side) with weight w.
  void add(long i, long j, const Eigen::Matrix3d& M, const Eigen::Matrix3d& b, double w,
           const Eigen::Matrix3d& x_anchor) {
    // Jacobians: d/dx_j = I, d/dx_i = -M.
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    Eigen::Matrix3d rhs = b;  // the constant part moved to the right: x_j - M x_i = b
    if (i < 0) rhs += M * x_anchor;
    if (j < 0) rhs -= x_anchor;
    if (j >= 0) {
      addBlock(j, j, w * I);
      g.middleRows<3>(3 * j) += w * rhs;
    }
    if (i >= 0) {
      addBlock(i, i, w * M.transpose() * M);
      g.middleRows<3>(3 * i) -= w * M.transpose() * rhs;
    }
    if (i >= 0 && j >= 0) {
      addBlock(i, j, -w * M.transpose());
      addBlock(j, i, -w * M);
    }
  }
};

Result<Eigen::MatrixXd> solve(NormalEquations& equations, size_t num_unknowns) {
  SparseMatrix H(static_cast<long>(3 * num_unknowns), static_cast<long>(3 * num_unknowns));
  H.setFromTriplets(equations.H.begin(), equations.H.end());
  Eigen::SimplicialLDLT<SparseMatrix> solver(H);
  if (solver.info() != Eigen::Success) return Error{"chordal initialization: singular system"};
  Eigen::MatrixXd x = solver.solve(equations.g);
  if (solver.info() != Eigen::Success || !x.allFinite()) {
    return Error{"chordal initialization: the linear solve failed"};
  }
  return x;
}

}  // namespace

Result<std::map<NodeId, Eigen::Isometry3d>> chordalInitialization(const PoseGraph& graph,
                                                                  NodeId anchor,
                                                                  const EdgeFilter& use_edge) {
  std::vector<const PoseGraphEdge*> edges;
  for (const PoseGraphEdge& edge : graph.edges) {
    if (edge.from != edge.to && (!use_edge || use_edge(edge))) edges.push_back(&edge);
  }
  const std::vector<NodeId> nodes = connectedNodes(edges, anchor);
  if (nodes.size() < 2)
    return Error{"chordal initialization: anchor " + anchor.str() + " has no edge"};
  // Unknown index of each node; the anchor is -1 (known).
  std::unordered_map<NodeId, long> unknown;
  for (size_t k = 0; k < nodes.size(); ++k) unknown[nodes[k]] = static_cast<long>(k) - 1;
  const size_t n = nodes.size() - 1;

  // Rotations: residual y_j - R_ij^T y_i, one right-hand side per row k of the rotations.
  NormalEquations rotation(n);
  for (const PoseGraphEdge* e : edges) {
    const auto i = unknown.find(e->from), j = unknown.find(e->to);
    if (i == unknown.end() || j == unknown.end()) continue;
    rotation.add(i->second, j->second, e->T_from_to.linear().transpose(), Eigen::Matrix3d::Zero(),
                 isotropicWeights(e->information).kappa, Eigen::Matrix3d::Identity());
  }
  auto y = solve(rotation, n);
  if (!y) return Error{y.error()};
  std::vector<Eigen::Matrix3d> R(nodes.size(), Eigen::Matrix3d::Identity());
  for (size_t k = 1; k < nodes.size(); ++k) {
    // Column c of y's block is y^(c) = R^T e_c, i.e. the block is R^T.
    R[k] = projectToSO3(y.value().middleRows<3>(3 * static_cast<long>(k - 1)).transpose());
  }

  // Translations: residual t_j - t_i - R_i t_ij (M = I); t_i is the first column of node i's
  // unknown block, the other two columns stay zero.
  NormalEquations translation(n);
  for (const PoseGraphEdge* e : edges) {
    const auto i = unknown.find(e->from), j = unknown.find(e->to);
    if (i == unknown.end() || j == unknown.end()) continue;
    const Eigen::Vector3d b = R[static_cast<size_t>(i->second + 1)] * e->T_from_to.translation();
    Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
    B.col(0) = b;
    translation.add(i->second, j->second, Eigen::Matrix3d::Identity(), B,
                    isotropicWeights(e->information).tau, Eigen::Matrix3d::Zero());
  }
  auto t = solve(translation, n);
  if (!t) return Error{t.error()};

  std::map<NodeId, Eigen::Isometry3d> poses;
  for (size_t k = 0; k < nodes.size(); ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R[k];
    if (k > 0) T.translation() = t.value().block<3, 1>(3 * static_cast<long>(k - 1), 0);
    poses[nodes[k]] = T;
  }
  return poses;
}

}  // namespace hydra_multi
