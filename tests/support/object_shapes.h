#pragma once
// Object surfaces for registration and reconciliation tests.

#include <Eigen/Core>
#include <vector>

namespace hydra_multi::testing {

/// The vertices of a box of `size` meshed as the simulator meshes objects: a lattice of 4 points
/// per edge (0.25-0.3 m apart for furniture), the points on its faces, about the box's centre.
std::vector<Eigen::Vector3d> latticeBoxVertices(const Eigen::Vector3d& size);

}  // namespace hydra_multi::testing
