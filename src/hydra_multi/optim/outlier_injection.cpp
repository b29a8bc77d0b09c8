#include "hydra_multi/optim/outlier_injection.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace hydra_multi {
namespace {

// A uniformly random rotation (Shoemake 1992), from our seeded generator.
Eigen::Quaterniond randomRotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double u1 = u(rng), u2 = 2.0 * M_PI * u(rng), u3 = 2.0 * M_PI * u(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  return Eigen::Quaterniond(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3));
}

}  // namespace

size_t injectOutliers(PoseGraph& graph, const std::map<NodeId, Eigen::Isometry3d>& poses,
                      double fraction, uint64_t seed) {
  if (fraction <= 0.0 || fraction >= 1.0 || poses.size() < 3) return 0;
  std::vector<const PoseGraphEdge*> loop_closures;
  for (const PoseGraphEdge& e : graph.edges) {
    if (e.kind == PoseGraphEdge::Kind::kLoopClosure) loop_closures.push_back(&e);
  }
  Matrix6d information = Matrix6d::Identity();
  if (!loop_closures.empty()) {
    std::sort(loop_closures.begin(), loop_closures.end(),
              [](const PoseGraphEdge* x, const PoseGraphEdge* y) {
                return x->information.trace() < y->information.trace();
              });
    information = loop_closures[loop_closures.size() / 2]->information;
  }
  const double L = static_cast<double>(loop_closures.size());
  const size_t count = static_cast<size_t>(std::llround(fraction * L / (1.0 - fraction)));

  std::vector<NodeId> ids;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& [id, T] : poses) {
    ids.push_back(id);
    lo = lo.cwiseMin(T.translation());
    hi = hi.cwiseMax(T.translation());
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, ids.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (size_t n = 0; n < count; ++n) {
    size_t i = pick(rng), j = pick(rng);
    while (i == j || i + 1 == j || j + 1 == i) j = pick(rng);
    PoseGraphEdge e;
    e.from = ids[i];
    e.to = ids[j];
    e.kind = PoseGraphEdge::Kind::kLoopClosure;
    e.T_from_to.linear() = randomRotation(rng).toRotationMatrix();
    for (int k = 0; k < 3; ++k) e.T_from_to.translation()[k] = lo[k] + unit(rng) * (hi[k] - lo[k]);
    e.information = information;
    graph.edges.push_back(e);
  }
  return count;
}

}  // namespace hydra_multi
