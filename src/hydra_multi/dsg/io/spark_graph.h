#pragma once
// Spark-DSG's binary graph (spark_binary.h) to our scene graph and back.
//   layer 2, partition 0 -> objects    layer 2, another partition (the robot's prefix) -> agents
//   layer 3, partition 0 -> places     layer 4 -> rooms    layer 5 -> buildings
// Attributes as in spark_json.h: agents position, world_R_body, timestamp, external_key <->
// keyframe_id; semantic nodes label, name, colour (alpha dropped), bounding box (an axis-aligned
// box of its dimensions about its centre; INVALID: none); objects mesh_connections and places
// pcl_mesh_connections <-> mesh vertices; places distance; every node last_update_time_ns (an
// unset stamp above 2^63 - 1 is taken as 0) and is_active; edges weight and weighted; the mesh's
// points, colours, labels and last-seen stamps. Layers our graph has no place for (2D places in
// layer 3 partition 1, others) and their edges are left out and counted.
// Our graph in Spark's form: node ids as they are (a station id keeps its robot in bits 48-54 of
// the index, so ids stay unique across robots), each node's metadata naming its robot and readable
// id ({"robot": "b", "id": "O(3)@b"}), agents in the partition of their prefix character, every
// layer key listed, types from Spark-DSG's registered names; Spark's mesh has no robot per vertex,
// so the graph's metadata holds the runs of each robot's vertices
// ({"hydra_multi": {"mesh_robots": [["a", 0, 5763], ["b", 5763, 5490]]}}), which the import reads.

#include <map>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::io {

struct SparkImport {
  SceneGraph graph;
  /// What was left out: "nodes of layer 3 partition 1" -> count, "edges to them" -> count, ...
  std::map<std::string, size_t> left_out;
};

Result<SparkImport> sceneGraphFromSpark(const spark::Graph& spark);
spark::Graph sparkFromSceneGraph(const SceneGraph& graph, bool include_mesh = true);

/// Moves a graph as a robot whose odometric frame is turned by `yaw` (rad, about z) and offset by
/// `offset` would have mapped it (p' = R p + t): node positions, agents' and objects'
/// orientations, boxes (an AABB becomes the AABB of the turned box; oriented boxes turn), places'
/// frontier orientations, 2D places' boundaries and ellipses, the mesh.
void moveSparkGraph(spark::Graph& graph, const Eigen::Vector3d& offset, double yaw);

/// A .sparkdsg file's bytes to our graph (what was left out is dropped; use the two steps to see
/// it), and our graph to a .sparkdsg file's bytes.
Result<SceneGraph> sceneGraphFromSparkFile(const std::string& bytes);
std::string sceneGraphToSparkFile(const SceneGraph& graph);

}  // namespace hydra_multi::io
