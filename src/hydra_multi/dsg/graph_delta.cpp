#include "hydra_multi/dsg/graph_delta.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

namespace hydra_multi {
namespace {

template <typename T>
size_t firstDifference(const std::vector<T>& a, const std::vector<T>& b) {
  const size_t n = std::min(a.size(), b.size());
  size_t i = 0;
  while (i < n && a[i] == b[i]) ++i;
  return i;
}

std::string edgeName(size_t index, NodeId a, NodeId b) {
  return "edge " + std::to_string(index) + " (" + a.str() + " - " + b.str() + ")";
}

// Checks the whole delta against the graph without changing it.
Status checkDelta(const SceneGraph& graph, const GraphDelta& delta) {
  // The layer of every node after the delta, where it differs from the graph's.
  std::map<NodeId, std::optional<Layer>> changed_layers;
  for (const NodeId id : delta.removed_nodes) changed_layers[id] = std::nullopt;
  std::set<NodeId> seen;
  for (size_t i = 0; i < delta.nodes.size(); ++i) {
    const Node& node = delta.nodes[i];
    const std::string where = "node " + std::to_string(i) + " (" + node.id.str() + ")";
    if (!seen.insert(node.id).second) return Error{where + ": given twice"};
    if (Status status = validateNode(node); !status) return Error{where + ": " + status.message()};
    const Node* existing = graph.findNode(node.id);
    const bool removed_first = std::find(delta.removed_nodes.begin(), delta.removed_nodes.end(),
                                         node.id) != delta.removed_nodes.end();
    if (existing && !removed_first && existing->layer() != node.layer()) {
      return Error{where + ": exists in layer " + layerName(existing->layer()) + ", not " +
                   layerName(node.layer())};
    }
    changed_layers[node.id] = node.layer();
  }
  auto layerAfter = [&](NodeId id) -> std::optional<Layer> {
    if (auto it = changed_layers.find(id); it != changed_layers.end()) return it->second;
    if (const Node* node = graph.findNode(id)) return node->layer();
    return std::nullopt;
  };
  for (size_t i = 0; i < delta.edges.size(); ++i) {
    const Edge& edge = delta.edges[i];
    const std::string where = edgeName(i, edge.source, edge.target);
    if (edge.source == edge.target) return Error{where + ": self-loop"};
    if (!std::isfinite(edge.info.weight)) return Error{where + ": weight is not finite"};
    const auto layer_a = layerAfter(edge.source);
    const auto layer_b = layerAfter(edge.target);
    if (!layer_a || !layer_b) {
      return Error{where + ": endpoint " + (layer_a ? edge.target : edge.source).str() +
                   " does not exist"};
    }
    if (!isValidEdge(*layer_a, *layer_b)) {
      return Error{where + ": layers " + std::string(layerName(*layer_a)) + " and " +
                   layerName(*layer_b) + " may not be joined"};
    }
  }
  const MeshDelta& mesh = delta.mesh;
  const Mesh& old_mesh = graph.mesh();
  if (mesh.vertex_start > old_mesh.vertices.size()) {
    return Error{"mesh: vertex_start " + std::to_string(mesh.vertex_start) + " is past the " +
                 std::to_string(old_mesh.vertices.size()) + " vertices of the mesh"};
  }
  if (mesh.face_start > old_mesh.faces.size()) {
    return Error{"mesh: face_start " + std::to_string(mesh.face_start) + " is past the " +
                 std::to_string(old_mesh.faces.size()) + " faces of the mesh"};
  }
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].position.allFinite()) {
      return Error{"mesh vertex " + std::to_string(mesh.vertex_start + i) +
                   ": position is not finite"};
    }
    if (!mesh.vertices[i].robot.isValid()) {
      return Error{"mesh vertex " + std::to_string(mesh.vertex_start + i) + ": robot index " +
                   std::to_string(mesh.vertices[i].robot.index()) + " is not valid"};
    }
  }
  const uint64_t num_vertices = mesh.vertex_start + mesh.vertices.size();
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    for (const uint32_t v : mesh.faces[f]) {
      if (v >= num_vertices) {
        return Error{"mesh face " + std::to_string(mesh.face_start + f) + ": vertex " +
                     std::to_string(v) + " does not exist (" + std::to_string(num_vertices) +
                     " vertices)"};
      }
    }
  }
  // Faces kept from before must still point at existing vertices.
  for (size_t f = 0; f < mesh.face_start; ++f) {
    for (const uint32_t v : old_mesh.faces[f]) {
      if (v >= num_vertices) {
        return Error{"mesh: cutting at vertex " + std::to_string(mesh.vertex_start) +
                     " leaves face " + std::to_string(f) + " without its vertex " +
                     std::to_string(v)};
      }
    }
  }
  return Status::Ok();
}

}  // namespace

GraphDelta diffGraphs(const SceneGraph& from, const SceneGraph& to) {
  GraphDelta delta;
  for (const auto& [id, node] : from.nodes()) {
    const Node* other = to.findNode(id);
    // A node that changes layer is removed and added again.
    if (!other || other->layer() != node.layer()) delta.removed_nodes.push_back(id);
  }
  for (const auto& [id, node] : to.nodes()) {
    const Node* old = from.findNode(id);
    if (!old || *old != node) delta.nodes.push_back(node);
  }
  const std::set<NodeId> removed(delta.removed_nodes.begin(), delta.removed_nodes.end());
  for (const auto& [key, info] : from.edges()) {
    // Edges of removed nodes go with them.
    if (removed.count(key.first()) || removed.count(key.second())) continue;
    if (!to.findEdge(key.first(), key.second())) delta.removed_edges.push_back(key);
  }
  for (const auto& [key, info] : to.edges()) {
    const bool endpoint_readded = removed.count(key.first()) || removed.count(key.second());
    const EdgeAttributes* old = from.findEdge(key.first(), key.second());
    if (endpoint_readded || !old || !(*old == info)) {
      delta.edges.push_back({key.first(), key.second(), info});
    }
  }
  const Mesh& a = from.mesh();
  const Mesh& b = to.mesh();
  const size_t v0 = firstDifference(a.vertices, b.vertices);
  const size_t f0 = firstDifference(a.faces, b.faces);
  delta.mesh.vertex_start = v0;
  delta.mesh.vertices.assign(b.vertices.begin() + static_cast<std::ptrdiff_t>(v0),
                             b.vertices.end());
  delta.mesh.face_start = f0;
  delta.mesh.faces.assign(b.faces.begin() + static_cast<std::ptrdiff_t>(f0), b.faces.end());
  return delta;
}

GraphDelta snapshotOf(const SceneGraph& graph) { return diffGraphs(SceneGraph(), graph); }

Status applyDelta(SceneGraph& graph, const GraphDelta& delta) {
  if (Status status = checkDelta(graph, delta); !status) return status;
  for (const EdgeKey& key : delta.removed_edges) graph.removeEdge(key.first(), key.second());
  for (const NodeId id : delta.removed_nodes) graph.removeNode(id);
  for (const Node& node : delta.nodes) graph.addOrUpdateNode(node);
  for (const Edge& edge : delta.edges) graph.addOrUpdateEdge(edge.source, edge.target, edge.info);
  Mesh& mesh = graph.mesh();
  mesh.vertices.resize(delta.mesh.vertex_start);
  mesh.vertices.insert(mesh.vertices.end(), delta.mesh.vertices.begin(), delta.mesh.vertices.end());
  mesh.faces.resize(delta.mesh.face_start);
  mesh.faces.insert(mesh.faces.end(), delta.mesh.faces.begin(), delta.mesh.faces.end());
  return Status::Ok();
}

Result<SceneGraph> graphFromSnapshot(const GraphDelta& snapshot) {
  SceneGraph graph;
  if (Status status = applyDelta(graph, snapshot); !status) return Error{status.message()};
  return graph;
}

}  // namespace hydra_multi
