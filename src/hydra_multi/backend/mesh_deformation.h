#pragma once
// Mesh deformation (Sumner 2007, Kimera-PGMO): after the solve, each mesh vertex moves with its k
// nearest control points among those its robot made within a window of the vertex's time
// (TimedNeighbors):
//   v' = sum_j w_j (R_j R0_j^T (v - g_j) + t_j) / sum_j w_j,   w_j = 1 - d_j / d_max,
// with g_j, R0_j a control point's initial position and rotation, (R_j, t_j) its optimized pose,
// and d_max the distance to the (k+1)-th nearest control point. A round binds (the neighbours and
// weights) only the vertices a control point made since the last round may reach and blends
// only those whose control points moved (MeshBinding); the result is a fresh deformMesh's.
// docs/DECISIONS.md: "The mesh bound once, blended where it moved".

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "hydra_multi/dsg/mesh.h"

namespace hydra_multi {

/// Moves mesh vertices (global frame, before optimization) with their k nearest control points
/// among those made within `window_s` of the vertex (TimedNeighbors; <= 0: any): `initial` and
/// `optimized` poses of the control points, `times_ns` when the robot made each.
void deformMesh(std::vector<MeshVertex>& vertices, const std::vector<Eigen::Isometry3d>& initial,
                const std::vector<Eigen::Isometry3d>& optimized,
                const std::vector<int64_t>& times_ns, double window_s, size_t k = 4);

/// One robot's mesh bound to its control points for deformMesh's blend, kept from round to round:
/// per vertex its k nearest control points made within the window of its time and their weights
/// w_j = 1 - d_j / d_max, and the vertex as blended last. Distances do not depend on the frame, so
/// a binding made in the robot's frame holds through re-alignments.
struct MeshBinding {
  size_t k = 0;
  double window_s = 0.0;
  std::vector<Eigen::Vector3d> control_points;  ///< positions as bound
  std::vector<int64_t> control_point_times;
  std::vector<MeshVertex> vertices;   ///< as bound
  std::vector<uint32_t> neighbours;   ///< k per vertex (control point indices), count below
  std::vector<double> weights;        ///< k per vertex, normalized
  std::vector<uint8_t> count;         ///< neighbours per vertex
  std::vector<uint8_t> window_moved;  ///< the vertex's window held no control point
  /// The last blend: its control points' poses (initial, optimized; global) and the vertices.
  std::vector<Eigen::Isometry3d> blended_initial, blended_optimized;
  std::vector<Eigen::Vector3f> blended;
  size_t bound = 0, reblended = 0;  ///< vertices bound and blended by the last call
};

/// Binds `vertices` to the control points at `positions` made at `times_ns` (both in one frame, the
/// robot's), reusing `binding`'s earlier bindings where nothing can change them: the vertex as it
/// was, the earlier control points unchanged, and no control point new since made within the
/// window of the vertex's time (nor any at all where its window held none). The same binding as a
/// fresh one.
void bindMesh(MeshBinding& binding, const std::vector<MeshVertex>& vertices,
              const std::vector<Eigen::Vector3d>& positions, const std::vector<int64_t>& times_ns,
              double window_s, size_t k);

/// The bound vertices deformed (deformMesh's blend): `aligned` each vertex of the binding in the
/// global frame, `initial` and `optimized` the control points' poses there. A vertex whose bound
/// control points kept their poses since the last blend, itself unchanged, keeps its result.
std::vector<Eigen::Vector3f> blendMesh(MeshBinding& binding,
                                       const std::vector<Eigen::Vector3f>& aligned,
                                       const std::vector<Eigen::Isometry3d>& initial,
                                       const std::vector<Eigen::Isometry3d>& optimized);

}  // namespace hydra_multi
