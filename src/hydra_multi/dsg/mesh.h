#pragma once
// The mesh layer: vertices with position, colour, semantic label, owning robot and time; triangle
// faces. Positions are single precision, as in Hydra and Spark-DSG.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "hydra_multi/core/robot_id.h"
#include "hydra_multi/dsg/node.h"

namespace hydra_multi {

struct MeshVertex {
  /// The label of a vertex that has none (e.g. from a lidar robot without semantics).
  static constexpr uint32_t kUnlabeled = std::numeric_limits<uint32_t>::max();

  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Color color;
  uint32_t label = kUnlabeled;
  RobotId robot;
  int64_t time_ns = 0;

  bool operator==(const MeshVertex& o) const {
    return position == o.position && color == o.color && label == o.label && robot == o.robot &&
           time_ns == o.time_ns;
  }
};

using MeshFace = std::array<uint32_t, 3>;

struct Mesh {
  std::vector<MeshVertex> vertices;
  std::vector<MeshFace> faces;

  bool empty() const { return vertices.empty() && faces.empty(); }
  bool operator==(const Mesh& o) const { return vertices == o.vertices && faces == o.faces; }
  bool operator!=(const Mesh& o) const { return !(*this == o); }
};

/// Checks finite positions and face indices below the vertex count; the message names the first
/// offending vertex or face.
Status validateMesh(const Mesh& mesh);

}  // namespace hydra_multi
