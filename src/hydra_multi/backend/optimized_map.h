#pragma once
// The backend graph of a round (paper III-B; backend.h step 4): every aligned robot's keyframes
// and places at their optimized poses; its mesh aligned into the global frame and deformed with
// its control points (mesh_deformation.h); its objects moved as their mesh vertices
// moved, or, without vertices, as their nearest control point of about their time moved, their
// boxes with them; its edges as the frontend has them. The robots' meshes are appended in order,
// object vertex indices offset accordingly. Rooms and buildings are left to room segmentation.

#include <map>
#include <vector>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/backend/mesh_deformation.h"

namespace hydra_multi {

/// `robots`: the aligned robots as the deformation graph took them; `deformation` and `poses`: the
/// deformation graph and its optimized poses. `first_keyframes` (when given) receives each
/// robot's first keyframe's optimized pose. `bindings` (when given) holds each robot's mesh as
/// bound and blended by the last call, read and updated (MeshBinding: the same result as without).
SceneGraph optimizedMap(const SceneGraph& frontend,
                        const std::vector<RobotDeformationInput>& robots,
                        const DeformationGraph& deformation,
                        const std::map<NodeId, Eigen::Isometry3d>& poses,
                        const DeformationGraphOptions& options, size_t mesh_neighbours,
                        std::map<RobotId, Eigen::Isometry3d>* first_keyframes = nullptr,
                        std::map<RobotId, MeshBinding>* bindings = nullptr);

}  // namespace hydra_multi
