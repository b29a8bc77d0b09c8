#include "hydra_multi/dsg/graph_summary.h"

#include <numeric>

namespace hydra_multi {

size_t RobotSummary::numNodes() const {
  return std::accumulate(nodes_per_layer.begin(), nodes_per_layer.end(), size_t{0});
}

GraphSummary summarize(const SceneGraph& graph) {
  GraphSummary summary;
  summary.nodes = graph.numNodes();
  summary.edges = graph.numEdges();
  for (const auto& [id, node] : graph.nodes()) {
    const auto layer = static_cast<size_t>(node.layer());
    ++summary.nodes_per_layer[layer];
    if (const auto robot = node.robot()) ++summary.robots[*robot].nodes_per_layer[layer];
  }
  summary.mesh_vertices = graph.mesh().vertices.size();
  summary.mesh_faces = graph.mesh().faces.size();
  for (const MeshVertex& vertex : graph.mesh().vertices)
    ++summary.robots[vertex.robot].mesh_vertices;
  return summary;
}

}  // namespace hydra_multi
