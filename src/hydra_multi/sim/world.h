#pragma once
// The simulated world (ground truth): floors, rooms with doors, furniture objects with semantic
// labels. Only the simulator and the evaluation see it; robots sense it through their own sensor
// and odometry models, and the station never reads it.
//
// Frames: world z is up; a floor's rooms are axis-aligned rectangles in x-y at that floor's z;
// an object's T_world_object places its box (extents `size`, centred at the object frame's
// origin, base on the floor).

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "hydra_multi/dsg/node.h"

namespace hydra_multi::sim {

/// An axis-aligned rectangle in x-y.
struct Rect {
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
  Eigen::Vector2d center() const { return 0.5 * (min + max); }
  Eigen::Vector2d size() const { return max - min; }
  bool contains(const Eigen::Vector2d& p, double margin = 0.0) const;
  /// Interiors overlap (touching edges do not count).
  bool overlaps(const Rect& other) const;
};

enum class RoomKind : uint8_t {
  kCorridor,
  kOffice,
  kStudentRoom,
  kKitchen,
  kOpenSpace,
  kStairwell
};
const char* roomKindName(RoomKind kind);

struct Room {
  int id = 0;
  RoomKind kind = RoomKind::kOffice;
  int floor = 0;
  Rect footprint;   ///< free interior, walls excluded
  int layout = -1;  ///< rooms with one layout id have identical furniture (aliasing); -1: own
  bool faces_positive_y = true;  ///< which way the room's door wall faces the corridor
  /// A corridor between identical rooms repeats its wall texture with this period along x (the
  /// room pitch), as repeated doors and fittings do; 0: no repetition.
  double texture_period = 0.0;
};

/// A door in the wall between two rooms of one floor; `center` lies on the shared wall.
struct Door {
  int room_a = 0, room_b = 0;
  int floor = 0;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double width = 0.9;
};

/// A staircase between two floors: it rises inside stairwell `lower_room` (on the lower floor) to
/// stairwell `upper_room` right above it, from `bottom` (x-y, lower floor) to `top` (x-y, upper
/// floor).
struct Stairs {
  int lower_room = 0, upper_room = 0;
  Eigen::Vector2d bottom = Eigen::Vector2d::Zero();
  Eigen::Vector2d top = Eigen::Vector2d::Zero();
};

struct Floor {
  int index = 0;
  double z = 0.0;       ///< floor surface height (m)
  double height = 3.0;  ///< floor to ceiling (m)
};

/// A semantic class: label id, name, colour, typical box extents.
struct SemanticClass {
  uint32_t label = 0;
  std::string name;
  Color color;
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
};

struct ObjectInstance {
  int id = 0;
  uint32_t label = 0;
  int room = 0;
  Eigen::Isometry3d T_world_object = Eigen::Isometry3d::Identity();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  ///< box extents in the object frame
};

struct World {
  std::vector<Floor> floors;
  std::vector<Room> rooms;
  std::vector<Door> doors;
  std::vector<Stairs> stairs;
  std::vector<ObjectInstance> objects;
  std::vector<SemanticClass> classes;

  const Room& room(int id) const { return rooms.at(static_cast<size_t>(id)); }
  /// T_world_room: origin at the footprint's centre on the floor, x along the corridor, y away
  /// from the room's door (docs/DEVELOPING.md); corridors are not turned.
  Eigen::Isometry3d roomFrame(const Room& room) const;
  const SemanticClass* findClass(uint32_t label) const;
};

/// The project's label space for simulated worlds (furniture and structure classes).
std::vector<SemanticClass> defaultSemanticClasses();

}  // namespace hydra_multi::sim
