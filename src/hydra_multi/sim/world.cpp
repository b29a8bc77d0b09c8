#include "hydra_multi/sim/world.h"

#include <cmath>

namespace hydra_multi::sim {

bool Rect::contains(const Eigen::Vector2d& p, double margin) const {
  return (p.array() >= min.array() + margin).all() && (p.array() <= max.array() - margin).all();
}

bool Rect::overlaps(const Rect& other) const {
  return (min.array() < other.max.array()).all() && (other.min.array() < max.array()).all();
}

const char* roomKindName(RoomKind kind) {
  switch (kind) {
    case RoomKind::kCorridor:
      return "corridor";
    case RoomKind::kOffice:
      return "office";
    case RoomKind::kStudentRoom:
      return "student room";
    case RoomKind::kKitchen:
      return "kitchen";
    case RoomKind::kOpenSpace:
      return "open space";
    case RoomKind::kStairwell:
      return "stairwell";
  }
  return "room";
}

Eigen::Isometry3d World::roomFrame(const Room& room) const {
  Eigen::Isometry3d T_world_room = Eigen::Isometry3d::Identity();
  T_world_room.translation() << room.footprint.center().x(), room.footprint.center().y(),
      floors.at(static_cast<size_t>(room.floor)).z;
  // A door on the room's +y wall means "away from the door" is world -y: turned by pi.
  if (room.kind != RoomKind::kCorridor && room.faces_positive_y) {
    T_world_room.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  return T_world_room;
}

const SemanticClass* World::findClass(uint32_t label) const {
  for (const SemanticClass& c : classes) {
    if (c.label == label) return &c;
  }
  return nullptr;
}

std::vector<SemanticClass> defaultSemanticClasses() {
  // Extents (x, y, z) in metres, from common furniture dimensions.
  return {
      {1, "wall", {200, 200, 200}, {1, 1, 1}},
      {2, "floor", {120, 120, 120}, {1, 1, 1}},
      {3, "ceiling", {230, 230, 230}, {1, 1, 1}},
      {4, "door", {140, 90, 40}, {0.9, 0.05, 2.0}},
      {5, "chair", {219, 128, 223}, {0.5, 0.5, 0.9}},
      {6, "desk", {160, 110, 60}, {1.4, 0.7, 0.75}},
      {7, "table", {180, 130, 70}, {1.2, 0.8, 0.75}},
      {8, "sofa", {70, 90, 160}, {2.0, 0.9, 0.85}},
      {9, "bed", {90, 160, 200}, {2.0, 0.9, 0.5}},
      {10, "shelf", {120, 80, 40}, {1.0, 0.35, 1.8}},
      {11, "wardrobe", {100, 70, 50}, {1.0, 0.6, 2.0}},
      {12, "plant", {40, 160, 60}, {0.4, 0.4, 1.0}},
      {13, "monitor", {30, 30, 30}, {0.55, 0.2, 0.45}},
      {14, "lamp", {240, 220, 120}, {0.3, 0.3, 1.5}},
      {15, "refrigerator", {220, 220, 230}, {0.7, 0.7, 1.8}},
      {16, "sink", {150, 200, 220}, {0.6, 0.5, 0.9}},
      {17, "cabinet", {130, 100, 80}, {0.8, 0.5, 0.9}},
      {18, "whiteboard", {250, 250, 250}, {1.5, 0.05, 1.0}},
      {19, "trash can", {80, 80, 80}, {0.35, 0.35, 0.6}},
      {20, "printer", {60, 60, 70}, {0.5, 0.45, 0.4}},
  };
}

}  // namespace hydra_multi::sim
