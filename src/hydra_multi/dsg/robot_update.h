#pragma once
// RobotUpdate: what one robot sends the station in one message (DESIGN.md "What a robot sends").
// Everything is in the robot's own odometric frame (its start pose), which the station does not
// know. A full snapshot (is_snapshot) is as valid as a delta.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/core/robot_id.h"
#include "hydra_multi/core/se3.h"
#include "hydra_multi/dsg/graph_delta.h"

namespace hydra_multi {

/// The layers a robot provides (heterogeneous teams, paper III-C), as bits.
enum ProvidedLayer : uint32_t {
  kProvidesAgents = 1u << 0,
  kProvidesObjects = 1u << 1,
  kProvidesPlaces = 1u << 2,
  kProvidesMesh = 1u << 3,
  kProvidesMeshLabels = 1u << 4,
  kProvidesVisual = 1u << 5,
};
/// A semantic RGB-D robot running Hydra provides everything.
inline constexpr uint32_t kProvidesAll = 0x3F;
/// Names of the bits above, for the readable formats.
const char* providedLayerName(uint32_t bit);

/// An edge of the robot's own pose graph between two of its keyframes (agent node ids).
struct PoseGraphEdge {
  enum class Kind : uint8_t { kOdometry = 0, kLoopClosure = 1 };
  NodeId from;
  NodeId to;
  Kind kind = Kind::kOdometry;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  Matrix6d information = Matrix6d::Identity();  ///< order: translation, then rotation

  bool operator==(const PoseGraphEdge& o) const {
    return from == o.from && to == o.to && kind == o.kind &&
           T_from_to.matrix() == o.T_from_to.matrix() && information == o.information;
  }
};

/// A mesh control point of the robot's deformation graph (a subsampled mesh vertex), attached to
/// the keyframe that observed it.
struct ControlPoint {
  uint64_t id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  int64_t time_ns = 0;
  NodeId keyframe;
  bool operator==(const ControlPoint& o) const {
    return id == o.id && position == o.position && time_ns == o.time_ns && keyframe == o.keyframe;
  }
};

struct ControlPointEdge {
  uint64_t from = 0;
  uint64_t to = 0;
  bool operator==(const ControlPointEdge& o) const { return from == o.from && to == o.to; }
};

struct DeformationGraphDelta {
  std::vector<ControlPoint> points;
  std::vector<ControlPointEdge> edges;
  bool operator==(const DeformationGraphDelta& o) const {
    return points == o.points && edges == o.edges;
  }
};

/// One entry of a sparse bag-of-words vector.
struct BowEntry {
  uint32_t word = 0;
  float weight = 0.0f;
  bool operator==(const BowEntry& o) const { return word == o.word && weight == o.weight; }
};

/// A 3D keypoint in the keyframe's body frame, with its visual word.
struct Keypoint {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  uint32_t word = 0;
  bool operator==(const Keypoint& o) const { return position == o.position && word == o.word; }
};

struct KeyframeDescriptor {
  NodeId keyframe;
  std::vector<BowEntry> bow;
  std::vector<Keypoint> keypoints;
  bool operator==(const KeyframeDescriptor& o) const {
    return keyframe == o.keyframe && bow == o.bow && keypoints == o.keypoints;
  }
};

struct RobotUpdate {
  RobotId robot;
  uint64_t sequence = 0;
  int64_t time_ns = 0;
  bool is_snapshot = false;
  uint32_t provided_layers = kProvidesAll;
  GraphDelta graph;                       ///< nodes, edges and mesh of the local scene graph
  std::vector<PoseGraphEdge> pose_graph;  ///< odometry and intra-robot loop closures
  DeformationGraphDelta deformation;
  std::vector<KeyframeDescriptor> descriptors;

  bool operator==(const RobotUpdate& o) const {
    return robot == o.robot && sequence == o.sequence && time_ns == o.time_ns &&
           is_snapshot == o.is_snapshot && provided_layers == o.provided_layers &&
           graph == o.graph && pose_graph == o.pose_graph && deformation == o.deformation &&
           descriptors == o.descriptors;
  }
};

/// Checks what can be checked without the station's state: a valid robot, finite numbers, valid
/// nodes, unit rotations, symmetric information matrices with a non-negative diagonal, known
/// layer bits. The message names the robot, the sequence number and the item.
Status validateRobotUpdate(const RobotUpdate& update);

}  // namespace hydra_multi
