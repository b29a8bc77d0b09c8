#pragma once
// The backend graph of a round (paper III-B; backend.h step 4): every aligned robot's keyframes
// and places at their optimized poses; its mesh aligned into the global frame and deformed with
// its control points (mesh_deformation.h); its objects moved as their mesh vertices
// moved, or, without vertices, as their nearest control point of about their time moved, their
// boxes with them; its edges as the frontend has them. The robots' meshes are appended in order,
// object vertex indices offset accordingly. Rooms and buildings are left to room segmentation.
// Made in two steps: its nodes, edges and mesh as the frontend has them (unplacedMap, which needs
// no pose, so the backend makes it while the deformation graphs are solved), then placed
// (placeMap).

#include <map>
#include <vector>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/backend/mesh_deformation.h"

namespace hydra_multi {

/// `robots`: the aligned robots as the deformation graph takes them. Their keyframes, the places
/// of those with a keyframe (the nodes buildDeformationGraph poses, with or without merges), their
/// objects (mesh vertex indices offset), the frontend's edges between these, and their meshes
/// appended in order, all as the frontend has them.
SceneGraph unplacedMap(const SceneGraph& frontend,
                       const std::vector<RobotDeformationInput>& robots);

/// Places `map` (unplacedMap of the same frontend and robots) at the
/// deformation graph's optimized `poses`; a keyframe or place without one leaves. `first_keyframes`
/// (when given) receives each robot's first keyframe's optimized pose. `bindings` (when given)
/// holds each robot's mesh as bound and blended by the last call, read and updated (MeshBinding:
/// the same result as without). `placements` (when given): each node it holds gets the position and
/// box placeMap gives it, also where `map` no longer holds it (merged into another: planMerges).
void placeMap(SceneGraph& map, const SceneGraph& frontend,
              const std::vector<RobotDeformationInput>& robots, const DeformationGraph& deformation,
              const std::map<NodeId, Eigen::Isometry3d>& poses,
              const DeformationGraphOptions& options, size_t mesh_neighbours,
              std::map<RobotId, Eigen::Isometry3d>* first_keyframes = nullptr,
              std::map<RobotId, MeshBinding>* bindings = nullptr,
              std::map<NodeId, Placement>* placements = nullptr);

}  // namespace hydra_multi
