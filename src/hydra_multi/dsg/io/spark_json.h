#pragma once
// Spark-DSG JSON (.spark.json): import of the legacy layout Hydra wrote (top-level keys
// directed, edges, layer_ids, mesh_edges, mesh_layer_id, multigraph, nodes; see
// ../shared/data/dsg/apartment_dsg.json) and of the one Spark-DSG 1.1 writes (SPARK_DSG_header,
// layer_keys, nodes with a partition, colours {r, g, b, a}, boxes by dimensions about a centre,
// the agents' stamps in their attributes, uint64 stamps, a mesh: ../shared/data/spark/*.json);
// export in the legacy layout. Layers: 2 agents (nodes with a "prefix", or a partition) and
// objects, 3 places, 4 rooms, 5 buildings. Everything of our graph maps both ways but the mesh,
// which only the 1.1 layout holds (read, not written):
//   agents:  position, world_R_body, node "timestamp", external_key <-> keyframe_id
//   objects: semantic_label, name, color, bounding_box (AABB or INVALID), mesh_connections
//   places:  semantic fields, distance, pcl_mesh_connections <-> mesh_vertices
//   rooms, buildings: semantic fields
//   every node: last_update_time_ns, is_active; edges: info.weight, info.weighted
// Keys that Hydra writes and our graph does not model (voxblox_mesh_connections,
// deformation_connections, num_basis_points, registered, world_R_object, dbow ids) are read past on
// import and written with empty or identity values on export.

#include <nlohmann/json.hpp>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::io {

Result<SceneGraph> sceneGraphFromSparkJson(const std::string& text);
Result<SceneGraph> sceneGraphFromSparkJsonValue(const nlohmann::ordered_json& root);
/// The graph in Spark-DSG's layout (its mesh is not part of that layout and is left out).
std::string sceneGraphToSparkJson(const SceneGraph& graph);

}  // namespace hydra_multi::io
