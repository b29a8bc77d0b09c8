#include "hydra_multi/dsg/node.h"

#include <cmath>

namespace hydra_multi {

SemanticAttributes* Node::semantic() {
  return std::visit(
      [](auto& attributes) -> SemanticAttributes* {
        if constexpr (std::is_same_v<std::decay_t<decltype(attributes)>, AgentAttributes>) {
          return nullptr;
        } else {
          return &attributes.semantic;
        }
      },
      attributes);
}

const SemanticAttributes* Node::semantic() const { return const_cast<Node*>(this)->semantic(); }

std::optional<RobotId> Node::robot() const {
  if (layer() == Layer::kAgents) return RobotId::fromPrefix(id.category());
  return id.sourceRobot();
}

bool Node::operator==(const Node& o) const {
  return id == o.id && position == o.position && last_update_time_ns == o.last_update_time_ns &&
         is_active == o.is_active && attributes == o.attributes;
}

Node makeNode(NodeId id, Layer layer, const Eigen::Vector3d& position) {
  Node node;
  node.id = id;
  node.position = position;
  switch (layer) {
    case Layer::kAgents:
      node.attributes = AgentAttributes{};
      break;
    case Layer::kObjects:
      node.attributes = ObjectAttributes{};
      break;
    case Layer::kPlaces:
      node.attributes = PlaceAttributes{};
      break;
    case Layer::kRooms:
      node.attributes = RoomAttributes{};
      break;
    case Layer::kBuildings:
      node.attributes = BuildingAttributes{};
      break;
  }
  return node;
}

Status validateNode(const Node& node) {
  const std::string where = "node " + node.id.str() + ": ";
  if (!node.position.allFinite()) return Error{where + "position is not finite"};
  if (const auto* agent = node.find<AgentAttributes>()) {
    if (!agent->orientation.coeffs().allFinite()) return Error{where + "orientation is not finite"};
    if (std::abs(agent->orientation.norm() - 1.0) > 1e-3) {
      return Error{where + "orientation is not a unit quaternion (norm " +
                   std::to_string(agent->orientation.norm()) + ")"};
    }
  }
  if (const auto* place = node.find<PlaceAttributes>()) {
    if (!std::isfinite(place->distance) || place->distance < 0.0) {
      return Error{where + "place distance must be finite and >= 0"};
    }
  }
  if (const SemanticAttributes* semantic = node.semantic(); semantic && semantic->bounding_box) {
    const BoundingBox& box = *semantic->bounding_box;
    if (!box.min.allFinite() || !box.max.allFinite()) {
      return Error{where + "bounding box is not finite"};
    }
    if ((box.min.array() > box.max.array()).any()) {
      return Error{where + "bounding box min exceeds max"};
    }
  }
  return Status::Ok();
}

Eigen::Isometry3d nodePose(const Node& node) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (const AgentAttributes* agent = node.find<AgentAttributes>())
    T.linear() = agent->orientation.normalized().toRotationMatrix();
  T.translation() = node.position;
  return T;
}

}  // namespace hydra_multi
