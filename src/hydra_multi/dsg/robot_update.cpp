#include "hydra_multi/dsg/robot_update.h"

#include <cmath>

namespace hydra_multi {

const char* providedLayerName(uint32_t bit) {
  switch (bit) {
    case kProvidesAgents:
      return "agents";
    case kProvidesObjects:
      return "objects";
    case kProvidesPlaces:
      return "places";
    case kProvidesMesh:
      return "mesh";
    case kProvidesMeshLabels:
      return "mesh_labels";
    case kProvidesVisual:
      return "visual";
    default:
      return nullptr;
  }
}

Status validateRobotUpdate(const RobotUpdate& update) {
  const std::string where =
      "update " + std::to_string(update.sequence) + " of robot " +
      (update.robot.isValid() ? update.robot.str() : "#" + std::to_string(update.robot.index()));
  if (!update.robot.isValid()) return Error{where + ": robot index is not valid"};
  if ((update.provided_layers & ~kProvidesAll) != 0) {
    return Error{where + ": unknown provided-layer bits"};
  }
  for (const Node& node : update.graph.nodes) {
    if (Status status = validateNode(node); !status) return Error{where + ": " + status.message()};
  }
  for (size_t i = 0; i < update.graph.edges.size(); ++i) {
    if (!std::isfinite(update.graph.edges[i].info.weight)) {
      return Error{where + ": edge " + std::to_string(i) + ": weight is not finite"};
    }
  }
  for (size_t i = 0; i < update.graph.mesh.vertices.size(); ++i) {
    const MeshVertex& vertex = update.graph.mesh.vertices[i];
    if (!vertex.position.allFinite() || !vertex.robot.isValid()) {
      return Error{where + ": mesh vertex " + std::to_string(update.graph.mesh.vertex_start + i) +
                   ": position is not finite or robot is not valid"};
    }
  }
  for (size_t i = 0; i < update.pose_graph.size(); ++i) {
    const PoseGraphEdge& edge = update.pose_graph[i];
    const std::string item = where + ": pose graph edge " + std::to_string(i) + " (" +
                             edge.from.str() + " - " + edge.to.str() + ")";
    if (!edge.T_from_to.matrix().allFinite()) return Error{item + ": pose is not finite"};
    const Eigen::Matrix3d R = edge.T_from_to.linear();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0) {
      return Error{item + ": rotation is not a rotation matrix"};
    }
    if (edge.T_from_to.matrix().row(3) != Eigen::RowVector4d(0, 0, 0, 1)) {
      return Error{item + ": last row of the pose is not [0 0 0 1]"};
    }
    const Matrix6d& info = edge.information;
    if (!info.allFinite() || (info - info.transpose()).norm() > 1e-9 * (1.0 + info.norm()) ||
        (info.diagonal().array() < 0.0).any()) {
      return Error{item + ": information matrix is not finite, symmetric and non-negative"};
    }
  }
  for (size_t i = 0; i < update.deformation.points.size(); ++i) {
    if (!update.deformation.points[i].position.allFinite()) {
      return Error{where + ": control point " + std::to_string(update.deformation.points[i].id) +
                   ": position is not finite"};
    }
  }
  for (const KeyframeDescriptor& descriptor : update.descriptors) {
    const std::string item = where + ": descriptor of " + descriptor.keyframe.str();
    for (const BowEntry& entry : descriptor.bow) {
      if (!std::isfinite(entry.weight)) return Error{item + ": bag-of-words weight is not finite"};
    }
    for (const Keypoint& keypoint : descriptor.keypoints) {
      if (!keypoint.position.allFinite()) return Error{item + ": keypoint is not finite"};
    }
  }
  return Status::Ok();
}

}  // namespace hydra_multi
