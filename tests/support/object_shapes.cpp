#include "support/object_shapes.h"

namespace hydra_multi::testing {

std::vector<Eigen::Vector3d> latticeBoxVertices(const Eigen::Vector3d& size) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i <= 3; ++i)
    for (int j = 0; j <= 3; ++j)
      for (int k = 0; k <= 3; ++k) {
        const bool on_face = i == 0 || i == 3 || j == 0 || j == 3 || k == 0 || k == 3;
        if (on_face)
          points.push_back(Eigen::Vector3d(i, j, k).cwiseProduct(size) / 3.0 - 0.5 * size);
      }
  return points;
}

}  // namespace hydra_multi::testing
