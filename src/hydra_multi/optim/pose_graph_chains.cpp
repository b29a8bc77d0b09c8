#include "hydra_multi/optim/pose_graph_chains.h"

#include <array>
#include <unordered_map>
#include <unordered_set>

#include "hydra_multi/core/se3.h"

namespace hydra_multi {
namespace {

// Ad(T) on [rho; phi]: T exp(xi) = exp(Ad(T) xi) T.
Matrix6d adjoint(const Eigen::Isometry3d& T) {
  Matrix6d ad = Matrix6d::Zero();
  const Eigen::Matrix3d R = T.linear();
  ad.topLeftCorner<3, 3>() = R;
  ad.topRightCorner<3, 3>() = hat(T.translation()) * R;
  ad.bottomRightCorner<3, 3>() = R;
  return ad;
}

// Edge k oriented along a chain, with its noise on the right: Z and Sigma.
struct Oriented {
  Eigen::Isometry3d Z;
  Matrix6d covariance;
};
Oriented oriented(const PoseGraphEdge& e, bool reversed) {
  const Matrix6d covariance = e.information.inverse();
  if (!reversed) return {e.T_from_to, covariance};
  // T_to^-1 T_from = M exp(n)  =>  T_from^-1 T_to = M^-1 exp(-Ad(M) n).
  const Matrix6d ad = adjoint(e.T_from_to);
  return {e.T_from_to.inverse(), ad * covariance * ad.transpose()};
}

bool positiveDefinite(const Matrix6d& information) {
  const Eigen::LLT<Matrix6d> llt(0.5 * (information + information.transpose()));
  return llt.info() == Eigen::Success;
}

}  // namespace

ChainReduction findChains(const PoseGraph& graph,
                          const std::map<NodeId, Eigen::Isometry3d>& initial, NodeId anchor,
                          const std::set<NodeId>& constant) {
  const auto included = [&](const PoseGraphEdge& e) {
    return e.from != e.to && initial.count(e.from) != 0 && initial.count(e.to) != 0;
  };
  std::unordered_map<NodeId, std::vector<size_t>> incident;  // every pose's included edges
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (!included(e)) continue;
    incident[e.from].push_back(k);
    incident[e.to].push_back(k);
  }
  const auto chainable = [&](size_t k) {
    const PoseGraphEdge& e = graph.edges[k];
    return e.kind != PoseGraphEdge::Kind::kLoopClosure && positiveDefinite(e.information);
  };
  std::unordered_map<NodeId, std::array<size_t, 2>> interior;  // candidates, their two edges
  for (const auto& [id, edges] : incident) {
    if (edges.size() != 2 || id == anchor || constant.count(id) != 0) continue;
    if (chainable(edges[0]) && chainable(edges[1])) interior[id] = {edges[0], edges[1]};
  }
  ChainReduction reduction;
  if (interior.empty()) return reduction;

  std::vector<bool> in_chain(graph.edges.size(), false);
  std::unordered_set<NodeId> placed;  // interior poses some chain holds
  const auto walk = [&](NodeId from, size_t first) {
    PoseGraphChain chain;
    chain.from = from;
    NodeId at = from;
    size_t k = first;
    while (true) {
      const PoseGraphEdge& e = graph.edges[k];
      const bool reversed = e.from != at;
      const NodeId next = reversed ? e.from : e.to;
      chain.edges.push_back(k);
      chain.reversed.push_back(reversed);
      in_chain[k] = true;
      const auto it = interior.find(next);
      if (it == interior.end()) {
        chain.to = next;
        break;
      }
      chain.interior.push_back(next);
      placed.insert(next);
      k = it->second[0] == k ? it->second[1] : it->second[0];
      at = next;
    }
    reduction.chains.push_back(std::move(chain));
  };
  // From each end pose, in the order of the edges; then what is left: cycles of candidates alone,
  // each kept at the pose it is entered by.
  const auto walkFrom = [&](NodeId id, size_t k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (!in_chain[k] && interior.count(e.from == id ? e.to : e.from) != 0) walk(id, k);
  };
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (!included(e)) continue;
    for (const NodeId id : {e.from, e.to}) {
      if (interior.count(id) == 0) walkFrom(id, k);
    }
  }
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& e = graph.edges[k];
    if (!included(e) || in_chain[k]) continue;
    const auto it = interior.find(e.from);
    if (it == interior.end() || placed.count(e.from) != 0) continue;
    const std::array<size_t, 2> edges = it->second;
    interior.erase(it);
    walkFrom(e.from, edges[0]);
    walkFrom(e.from, edges[1]);
  }

  for (const PoseGraphChain& chain : reduction.chains) {
    PoseGraphEdge composed;
    composed.from = chain.from;
    composed.to = chain.to;
    composed.kind = PoseGraphEdge::Kind::kOdometry;
    Matrix6d covariance = Matrix6d::Zero();
    for (size_t i = 0; i < chain.edges.size(); ++i) {
      const Oriented z = oriented(graph.edges[chain.edges[i]], chain.reversed[i]);
      const Matrix6d ad = adjoint(z.Z.inverse());
      covariance = ad * covariance * ad.transpose() + z.covariance;
      composed.T_from_to = composed.T_from_to * z.Z;
    }
    covariance = 0.5 * (covariance + covariance.transpose());
    composed.information = covariance.inverse();
    composed.information = 0.5 * (composed.information + composed.information.transpose());
    reduction.composed.push_back(composed);
  }
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    if (!in_chain[k]) reduction.kept_edges.push_back(k);
  }
  return reduction;
}

void placeChainInteriors(const PoseGraph& graph, const ChainReduction& reduction,
                         std::map<NodeId, Eigen::Isometry3d>& poses) {
  for (size_t c = 0; c < reduction.chains.size(); ++c) {
    const PoseGraphChain& chain = reduction.chains[c];
    const auto from = poses.find(chain.from);
    const auto to = poses.find(chain.to);
    if (from == poses.end() || to == poses.end()) continue;
    const size_t m = chain.edges.size();
    std::vector<Oriented> z;
    z.reserve(m);
    for (size_t i = 0; i < m; ++i)
      z.push_back(oriented(graph.edges[chain.edges[i]], chain.reversed[i]));
    // A_k = Ad(S_k^-1), S_k = Z_{k+1} ... Z_m, from the last edge back.
    std::vector<Matrix6d> A(m);
    Eigen::Isometry3d S = Eigen::Isometry3d::Identity();
    for (size_t i = m; i-- > 0;) {
      A[i] = adjoint(S.inverse());
      S = z[i].Z * S;
    }
    const Eigen::Isometry3d& Z = reduction.composed[c].T_from_to;
    const Vector6d d = logSE3(Z.inverse() * from->second.inverse() * to->second);
    const Vector6d y = reduction.composed[c].information * d;  // Sigma^-1 d
    Eigen::Isometry3d T = from->second;
    for (size_t i = 0; i + 1 < m; ++i) {
      const Vector6d n = z[i].covariance * A[i].transpose() * y;
      T = T * z[i].Z * expSE3(n);
      poses[chain.interior[i]] = T;
    }
  }
}

}  // namespace hydra_multi
