#include "hydra_multi/sim/building_generator.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

namespace hydra_multi::sim {
namespace {

constexpr double kDoorClearance = 1.0;  ///< free depth inside a room behind its door (m)
constexpr double kWallMargin = 0.1;     ///< free gap between furniture and walls (m)
constexpr double kFurnitureGap = 0.15;  ///< free gap between pieces of furniture (m)

// A piece of furniture in the room frame.
struct Placement {
  uint32_t label;
  Eigen::Vector3d position;  // centre of the box; z of the box centre above the floor
  double yaw;                // multiple of pi/2
  Eigen::Vector3d size;
};

// What a room of a kind holds: labels, the first of a group stands on the floor and the rest
// stand on top of it ("desk" then "monitor").
std::vector<std::vector<uint32_t>> furnitureGroups(RoomKind kind) {
  switch (kind) {
    case RoomKind::kOffice:
      return {{6, 13}, {5}, {10}, {12}, {19}, {17}};
    case RoomKind::kStudentRoom:
      return {{9}, {6, 14}, {5}, {11}, {10}};
    case RoomKind::kKitchen:
      return {{7}, {5}, {5}, {15}, {16}, {17}, {19}};
    case RoomKind::kOpenSpace:  // the desk clusters are repeated by area (openSpaceGroups)
      return {{8}, {12}, {10}, {18}, {20}, {19}, {17}, {12}};
    case RoomKind::kCorridor:
    case RoomKind::kStairwell:
      return {};
  }
  return {};
}

// An open space holds one desk cluster (desk, monitor, chair) per 12 m^2 besides its furniture.
std::vector<std::vector<uint32_t>> openSpaceGroups(double area) {
  std::vector<std::vector<uint32_t>> groups;
  const int clusters = std::max(2, static_cast<int>(area / 12.0));
  for (int i = 0; i < clusters; ++i) {
    groups.push_back({6, 13});
    groups.push_back({5});
  }
  for (auto& g : furnitureGroups(RoomKind::kOpenSpace)) groups.push_back(g);
  return groups;
}

Rect footprintOf(const Eigen::Vector3d& position, double yaw, const Eigen::Vector3d& size) {
  const bool turned = std::abs(std::sin(yaw)) > 0.5;
  const Eigen::Vector2d half =
      0.5 * (turned ? Eigen::Vector2d(size.y(), size.x()) : size.head<2>());
  return {position.head<2>() - half, position.head<2>() + half};
}

// Samples a layout for a room of the given size (room frame: centre origin, y away from door).
std::vector<Placement> sampleLayout(RoomKind kind, double width, double depth,
                                    const std::vector<SemanticClass>& classes,
                                    std::mt19937_64& rng) {
  std::map<uint32_t, Eigen::Vector3d> sizes;
  for (const SemanticClass& c : classes) sizes[c.label] = c.size;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Placement> layout;
  std::vector<Rect> taken;
  // The door zone: the full width of the room, kDoorClearance deep from the door wall.
  taken.push_back({{-0.5 * width, -0.5 * depth}, {0.5 * width, -0.5 * depth + kDoorClearance}});
  const auto groups =
      kind == RoomKind::kOpenSpace ? openSpaceGroups(width * depth) : furnitureGroups(kind);
  for (const auto& group : groups) {
    const Eigen::Vector3d size = sizes.at(group.front());
    for (int attempt = 0; attempt < 200; ++attempt) {
      const double yaw = 0.5 * M_PI * std::floor(4.0 * unit(rng));
      const bool turned = std::abs(std::sin(yaw)) > 0.5;
      const Eigen::Vector2d extent = turned ? Eigen::Vector2d(size.y(), size.x()) : size.head<2>();
      const Eigen::Vector2d lo = Eigen::Vector2d(-0.5 * width, -0.5 * depth) + 0.5 * extent +
                                 Eigen::Vector2d::Constant(kWallMargin);
      const Eigen::Vector2d hi = Eigen::Vector2d(0.5 * width, 0.5 * depth) - 0.5 * extent -
                                 Eigen::Vector2d::Constant(kWallMargin);
      if ((hi.array() < lo.array()).any()) break;  // does not fit this room at all
      const Eigen::Vector3d position(lo.x() + unit(rng) * (hi.x() - lo.x()),
                                     lo.y() + unit(rng) * (hi.y() - lo.y()), 0.5 * size.z());
      Rect footprint = footprintOf(position, yaw, size);
      Rect padded{footprint.min.array() - kFurnitureGap, footprint.max.array() + kFurnitureGap};
      bool free = true;
      for (const Rect& other : taken) free = free && !padded.overlaps(other);
      if (!free) continue;
      taken.push_back(footprint);
      layout.push_back({group.front(), position, yaw, size});
      // The rest of the group stands on top, centred.
      double top = size.z();
      for (size_t k = 1; k < group.size(); ++k) {
        const Eigen::Vector3d on_top = sizes.at(group[k]);
        layout.push_back({group[k],
                          Eigen::Vector3d(position.x(), position.y(), top + 0.5 * on_top.z()), yaw,
                          on_top});
        top += on_top.z();
      }
      break;
    }
  }
  return layout;
}

}  // namespace

Status BuildingOptions::validate() const {
  if (floors < 1 || floors > 20) return Error{"floors must be 1 to 20"};
  if (rooms_per_side < 1 || rooms_per_side > 200) return Error{"rooms_per_side must be 1 to 200"};
  if (!(room_width >= 2.5 && room_width <= 30)) return Error{"room_width must be 2.5 to 30 m"};
  if (!(room_depth >= 2.5 && room_depth <= 30)) return Error{"room_depth must be 2.5 to 30 m"};
  if (!(corridor_width >= 1.0 && corridor_width <= 10))
    return Error{"corridor_width must be 1 to 10 m"};
  if (!(wall_thickness > 0 && wall_thickness <= 0.5))
    return Error{"wall_thickness must be in (0, 0.5] m"};
  if (!(floor_height >= 2.2 && floor_height <= 10))
    return Error{"floor_height must be 2.2 to 10 m"};
  if (room_kind == RoomKind::kCorridor) return Error{"room_kind cannot be corridor"};
  if (room_kind == RoomKind::kStairwell || room_kind == RoomKind::kOpenSpace)
    return Error{"room_kind must be office, student room or kitchen"};
  if (kitchen_every < 0) return Error{"kitchen_every must be >= 0"};
  if (random_kitchens < 0 || random_kitchens > rooms_per_side)
    return Error{"random_kitchens must be 0 to rooms_per_side"};
  if (open_spaces < 0 || open_spaces > rooms_per_side)
    return Error{"open_spaces must be 0 to rooms_per_side"};
  if (!(far_side_depth == 0.0 || (far_side_depth >= 2.5 && far_side_depth <= 40)))
    return Error{"far_side_depth must be 0 (room_depth) or 2.5 to 40 m"};
  if (floors > 1 && rooms_per_side < 2)
    return Error{"a building of several floors needs rooms_per_side >= 2 (one is the stairwell)"};
  return Status::Ok();
}

Result<World> generateBuilding(const BuildingOptions& options) {
  if (Status status = options.validate(); !status) return Error{"building: " + status.message()};
  World world;
  world.classes = defaultSemanticClasses();
  std::mt19937_64 rng(options.seed);
  const double w = options.room_width, d = options.room_depth, t = options.wall_thickness;
  const double cw = options.corridor_width;
  const double length = options.rooms_per_side * (w + t) - t;
  std::map<RoomKind, std::vector<Placement>> shared_layouts;

  for (int f = 0; f < options.floors; ++f) {
    world.floors.push_back({f, f * (options.floor_height + 0.3), options.floor_height});
    Room corridor;
    corridor.id = static_cast<int>(world.rooms.size());
    corridor.kind = RoomKind::kCorridor;
    corridor.floor = f;
    corridor.footprint = {{0.0, 0.0}, {length, cw}};
    if (options.identical_rooms) corridor.texture_period = w + t;
    world.rooms.push_back(corridor);
    // The rooms of a floor: (side, x0, width, kind); side 0 lies below the corridor.
    struct Slot {
      int side;
      double x0, width;
      RoomKind kind;
    };
    std::vector<Slot> slots;
    // Room numbers 0..rooms_per_side-1 lie on the near side, the rest on the far side.
    const auto isStairwell = [&](int n) {
      return options.floors > 1 && n == options.rooms_per_side - 1;
    };
    // Kitchens at drawn slots (the stairwell's excluded). No draw without them: the other
    // presets' buildings stay as they were.
    std::set<int> drawn_kitchens;
    if (options.random_kitchens > 0) {
      std::vector<int> numbers;
      for (int n = 0; n < 2 * options.rooms_per_side; ++n) {
        const bool far_open = options.open_spaces > 0 && n >= options.rooms_per_side;
        if (!isStairwell(n) && !far_open) numbers.push_back(n);
      }
      std::shuffle(numbers.begin(), numbers.end(), rng);
      for (int k = 0; k < options.random_kitchens && k < static_cast<int>(numbers.size()); ++k)
        drawn_kitchens.insert(numbers[k]);
    }
    const auto isKitchen = [&](int n) {
      return (options.kitchen_every > 0 &&
              n % options.kitchen_every == options.kitchen_every - 1) ||
             drawn_kitchens.count(n) > 0;
    };
    for (int i = 0; i < options.rooms_per_side; ++i) {
      slots.push_back({0, i * (w + t), w,
                       isStairwell(i) ? RoomKind::kStairwell
                       : isKitchen(i) ? RoomKind::kKitchen
                                      : options.room_kind});
    }
    if (options.open_spaces > 0) {
      const double open_width = (length + t) / options.open_spaces - t;
      for (int i = 0; i < options.open_spaces; ++i)
        slots.push_back({1, i * (open_width + t), open_width, RoomKind::kOpenSpace});
    } else {
      for (int i = 0; i < options.rooms_per_side; ++i) {
        const bool kitchen = isKitchen(options.rooms_per_side + i);
        slots.push_back({1, i * (w + t), w, kitchen ? RoomKind::kKitchen : options.room_kind});
      }
    }
    const double far_depth = options.far_side_depth > 0.0 ? options.far_side_depth : d;
    for (const Slot& slot : slots) {
      Room room;
      room.id = static_cast<int>(world.rooms.size());
      room.floor = f;
      room.kind = slot.kind;
      const double depth = slot.side == 0 ? d : far_depth;
      const double x0 = slot.x0, rw = slot.width;
      room.faces_positive_y = slot.side == 0;  // side 0's door faces +y
      room.footprint = slot.side == 0 ? Rect{{x0, -t - d}, {x0 + rw, -t}}
                                      : Rect{{x0, cw + t}, {x0 + rw, cw + t + depth}};
      const double door_y = slot.side == 0 ? -0.5 * t : cw + 0.5 * t;
      if (rw > 10.0) {  // a wide open space: two doors
        world.doors.push_back({corridor.id, room.id, f, {x0 + 0.25 * rw, door_y}, 1.2});
        world.doors.push_back({corridor.id, room.id, f, {x0 + 0.75 * rw, door_y}, 1.2});
      } else {
        world.doors.push_back({corridor.id, room.id, f, {x0 + 0.5 * rw, door_y}, 0.9});
      }
      // Furniture: sampled per room, or once for all rooms of the building's kind when rooms
      // are identical (the student rooms of a dormitory; its kitchens differ from each other).
      std::vector<Placement> layout;
      if (room.kind == RoomKind::kStairwell) {
        // no furniture: the stairs take the room
      } else if (options.identical_rooms && room.kind == options.room_kind) {
        auto it = shared_layouts.find(room.kind);
        if (it == shared_layouts.end()) {
          it = shared_layouts
                   .emplace(room.kind, sampleLayout(room.kind, rw, depth, world.classes, rng))
                   .first;
        }
        layout = it->second;
        room.layout = static_cast<int>(room.kind);
      } else {
        layout = sampleLayout(room.kind, rw, depth, world.classes, rng);
      }
      world.rooms.push_back(room);
      const Eigen::Isometry3d T_world_room = world.roomFrame(room);
      for (const Placement& p : layout) {
        ObjectInstance object;
        object.id = static_cast<int>(world.objects.size());
        object.label = p.label;
        object.room = room.id;
        object.size = p.size;
        Eigen::Isometry3d T_room_object = Eigen::Isometry3d::Identity();
        T_room_object.translation() = p.position;
        T_room_object.linear() =
            Eigen::AngleAxisd(p.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        object.T_world_object = T_world_room * T_room_object;
        world.objects.push_back(object);
      }
    }
  }
  // Stairs: in the stairwell, from near its door on one floor to its far wall on the next.
  for (const Room& lower : world.rooms) {
    if (lower.kind != RoomKind::kStairwell) continue;
    for (const Room& upper : world.rooms) {
      if (upper.kind != RoomKind::kStairwell || upper.floor != lower.floor + 1) continue;
      const Eigen::Vector2d c = lower.footprint.center();
      const double half = 0.5 * lower.footprint.size().y();
      // Side 0 rooms have their door at +y: the stairs start there and rise towards -y.
      world.stairs.push_back(
          {lower.id, upper.id, {c.x(), c.y() + half - 1.2}, {c.x(), c.y() - half + 0.8}});
    }
  }
  return world;
}

}  // namespace hydra_multi::sim
