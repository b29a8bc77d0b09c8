#pragma once
// Counts of a scene graph per layer and per robot, for `hydra-multi info` and run summaries.

#include <array>
#include <cstddef>
#include <map>

#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct RobotSummary {
  std::array<size_t, kAllLayers.size()> nodes_per_layer{};  ///< indexed by Layer
  size_t mesh_vertices = 0;
  size_t numNodes() const;
};

struct GraphSummary {
  size_t nodes = 0;
  size_t edges = 0;
  std::array<size_t, kAllLayers.size()> nodes_per_layer{};  ///< indexed by Layer
  size_t mesh_vertices = 0;
  size_t mesh_faces = 0;
  std::map<RobotId, RobotSummary> robots;
};

GraphSummary summarize(const SceneGraph& graph);

}  // namespace hydra_multi
