#pragma once
// GraphDelta: the change that turns one scene graph into another: nodes added or changed (given
// whole), nodes removed, edges added or changed, edges removed, and the mesh from some vertex and
// face onwards. A full snapshot is the delta from the empty graph. Robots send deltas; files store
// snapshots; diffGraphs() computes one and applyDelta() applies one, all-or-nothing.

#include <cstdint>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

/// The mesh is cut at vertex_start and face_start and the given vertices and faces are appended:
/// appending new geometry keeps the starts at the old sizes; start 0 replaces the whole mesh.
struct MeshDelta {
  uint64_t vertex_start = 0;
  std::vector<MeshVertex> vertices;
  uint64_t face_start = 0;
  std::vector<MeshFace> faces;

  /// True when applying it changes nothing on a mesh of these sizes.
  bool isNoOp(size_t num_vertices, size_t num_faces) const {
    return vertices.empty() && faces.empty() && vertex_start == num_vertices &&
           face_start == num_faces;
  }
  bool operator==(const MeshDelta& o) const {
    return vertex_start == o.vertex_start && vertices == o.vertices && face_start == o.face_start &&
           faces == o.faces;
  }
};

struct GraphDelta {
  std::vector<Node> nodes;            ///< added or changed, whole
  std::vector<NodeId> removed_nodes;  ///< with their edges
  std::vector<Edge> edges;            ///< added or changed
  std::vector<EdgeKey> removed_edges;
  MeshDelta mesh;

  bool operator==(const GraphDelta& o) const {
    return nodes == o.nodes && removed_nodes == o.removed_nodes && edges == o.edges &&
           removed_edges == o.removed_edges && mesh == o.mesh;
  }
};

/// The delta that turns `from` into `to` (applyDelta(from, diff) == to).
GraphDelta diffGraphs(const SceneGraph& from, const SceneGraph& to);

/// The whole graph as a delta from the empty graph.
GraphDelta snapshotOf(const SceneGraph& graph);

/// Applies the delta in this order: removed edges, removed nodes, nodes, edges, mesh. Everything
/// is checked first (finite numbers, no layer changes, edge endpoints that exist afterwards and
/// layers that may be joined, mesh starts within the mesh, face indices within the vertices); on
/// an error the graph is left untouched and the message says what and which item.
Status applyDelta(SceneGraph& graph, const GraphDelta& delta);

/// Builds a graph from a snapshot; the same checks as applyDelta.
Result<SceneGraph> graphFromSnapshot(const GraphDelta& snapshot);

}  // namespace hydra_multi
