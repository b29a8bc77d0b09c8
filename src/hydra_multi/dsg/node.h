#pragma once
// Nodes and their attributes. Every node has a position, a last-update time and an is_active flag;
// the rest depends on its layer and lives in one alternative of a std::variant whose index is the
// layer, so attributes are reached by type (std::get_if), never by dynamic_cast.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "hydra_multi/core/node_id.h"
#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/layer.h"

namespace hydra_multi {

/// An RGB colour.
struct Color {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Color& o) const { return r == o.r && g == o.g && b == o.b; }
  bool operator!=(const Color& o) const { return !(*this == o); }
};

/// An axis-aligned bounding box in the graph's frame.
struct BoundingBox {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();

  Eigen::Vector3d center() const { return 0.5 * (min + max); }
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// The smallest box holding both.
  BoundingBox merged(const BoundingBox& other) const {
    return {min.cwiseMin(other.min), max.cwiseMax(other.max)};
  }
  bool operator==(const BoundingBox& o) const { return min == o.min && max == o.max; }
};

/// What objects, places, rooms and buildings share.
struct SemanticAttributes {
  uint32_t label = 0;  ///< semantic class id (decoded by a label space)
  std::string name;
  Color color;
  std::optional<BoundingBox> bounding_box;  ///< absent: no valid box
  bool operator==(const SemanticAttributes& o) const {
    return label == o.label && name == o.name && color == o.color && bounding_box == o.bounding_box;
  }
};

/// A keyframe pose of a robot.
struct AgentAttributes {
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< R_world_body
  int64_t timestamp_ns = 0;
  uint64_t keyframe_id = 0;  ///< the key of this pose in the robot's pose graph
  bool operator==(const AgentAttributes& o) const {
    return orientation.coeffs() == o.orientation.coeffs() && timestamp_ns == o.timestamp_ns &&
           keyframe_id == o.keyframe_id;
  }
};

struct ObjectAttributes {
  SemanticAttributes semantic;
  std::vector<uint64_t> mesh_vertices;  ///< indices of the mesh vertices that belong to the object
  bool operator==(const ObjectAttributes& o) const {
    return semantic == o.semantic && mesh_vertices == o.mesh_vertices;
  }
};

/// A free-space node on the medial axis, with its free-space radius.
struct PlaceAttributes {
  SemanticAttributes semantic;
  double distance = 0.0;                ///< distance to the nearest obstacle (m)
  std::vector<uint64_t> mesh_vertices;  ///< the nearest mesh vertices (its obstacles)
  bool operator==(const PlaceAttributes& o) const {
    return semantic == o.semantic && distance == o.distance && mesh_vertices == o.mesh_vertices;
  }
};

struct RoomAttributes {
  SemanticAttributes semantic;
  bool operator==(const RoomAttributes& o) const { return semantic == o.semantic; }
};

struct BuildingAttributes {
  SemanticAttributes semantic;
  bool operator==(const BuildingAttributes& o) const { return semantic == o.semantic; }
};

/// The layer-specific attributes; the alternative's index is the Layer's value.
using LayerAttributes = std::variant<AgentAttributes, ObjectAttributes, PlaceAttributes,
                                     RoomAttributes, BuildingAttributes>;

struct Node {
  NodeId id;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  int64_t last_update_time_ns = 0;
  bool is_active = true;
  LayerAttributes attributes;

  Layer layer() const { return static_cast<Layer>(attributes.index()); }
  template <typename T>
  const T* find() const {
    return std::get_if<T>(&attributes);
  }
  template <typename T>
  T* find() {
    return std::get_if<T>(&attributes);
  }
  /// The semantic attributes of an object, place, room or building; nullptr for agents.
  const SemanticAttributes* semantic() const;
  SemanticAttributes* semantic();
  /// The robot a node belongs to: an agent's robot by its prefix letter, otherwise the source
  /// robot of a station id; nullopt when neither says.
  std::optional<RobotId> robot() const;

  bool operator==(const Node& o) const;
  bool operator!=(const Node& o) const { return !(*this == o); }
};

/// A node's pose: its position, and for an agent its orientation (no rotation for the others).
Eigen::Isometry3d nodePose(const Node& node);

/// A node of `layer` with default attributes.
Node makeNode(NodeId id, Layer layer, const Eigen::Vector3d& position = Eigen::Vector3d::Zero());

/// Checks the numbers of a node: finite position, orientation and box, a unit quaternion, a
/// non-negative place distance, box min <= max. The message names the node.
Status validateNode(const Node& node);

}  // namespace hydra_multi
