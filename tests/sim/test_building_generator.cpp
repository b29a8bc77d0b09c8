#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hydra_multi/sim/building_generator.h"

namespace hydra_multi::sim {
namespace {

World generate(const BuildingOptions& options) {
  auto world = generateBuilding(options);
  EXPECT_TRUE(world.ok()) << world.error();
  return world.ok() ? std::move(world).value() : World();
}

Rect footprintOf(const ObjectInstance& o) {
  // The box's corners in x-y (yaw is a multiple of pi/2, so the footprint is axis-aligned).
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e9), hi = -lo;
  for (const double sx : {-0.5, 0.5}) {
    for (const double sy : {-0.5, 0.5}) {
      const Eigen::Vector3d corner =
          o.T_world_object * Eigen::Vector3d(sx * o.size.x(), sy * o.size.y(), 0.0);
      lo = lo.cwiseMin(corner.head<2>());
      hi = hi.cwiseMax(corner.head<2>());
    }
  }
  return {lo, hi};
}

Eigen::Isometry3d roomFrame(const World& world, const Room& room) { return world.roomFrame(room); }

// Same seed, same world; another seed, other furniture.
TEST(BuildingGenerator, DeterministicFromSeed) {
  BuildingOptions options;
  options.seed = 7;
  const World a = generate(options), b = generate(options);
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].label, b.objects[i].label);
    EXPECT_EQ(a.objects[i].T_world_object.matrix(), b.objects[i].T_world_object.matrix());
  }
  options.seed = 8;
  const World c = generate(options);
  bool differs = c.objects.size() != a.objects.size();
  for (size_t i = 0; !differs && i < a.objects.size(); ++i) {
    differs = a.objects[i].T_world_object.matrix() != c.objects[i].T_world_object.matrix();
  }
  EXPECT_TRUE(differs);
}

// Rooms of a floor never overlap; each room has one door on the wall it shares with the corridor.
TEST(BuildingGenerator, RoomsAndDoors) {
  BuildingOptions options;
  options.rooms_per_side = 5;
  const World world = generate(options);
  ASSERT_EQ(world.rooms.size(), 11u);  // corridor + 2 x 5
  for (const Room& a : world.rooms) {
    for (const Room& b : world.rooms) {
      if (a.id != b.id && a.floor == b.floor) {
        EXPECT_FALSE(a.footprint.overlaps(b.footprint));
      }
    }
  }
  ASSERT_EQ(world.doors.size(), 10u);
  for (const Door& door : world.doors) {
    const Room& corridor = world.room(door.room_a);
    const Room& room = world.room(door.room_b);
    EXPECT_EQ(corridor.kind, RoomKind::kCorridor);
    // The door lies between the two footprints, within the room's width.
    EXPECT_GT(door.center.x(), room.footprint.min.x() + 0.5 * door.width);
    EXPECT_LT(door.center.x(), room.footprint.max.x() - 0.5 * door.width);
    const double gap_room = std::min(std::abs(door.center.y() - room.footprint.min.y()),
                                     std::abs(door.center.y() - room.footprint.max.y()));
    const double gap_corridor = std::min(std::abs(door.center.y() - corridor.footprint.min.y()),
                                         std::abs(door.center.y() - corridor.footprint.max.y()));
    EXPECT_NEAR(gap_room, 0.5 * options.wall_thickness, 1e-9);
    EXPECT_NEAR(gap_corridor, 0.5 * options.wall_thickness, 1e-9);
  }
}

// Furniture stays inside its room, clear of walls, of each other and of the door zone; stacked
// objects stand on their base.
TEST(BuildingGenerator, FurnitureFitsItsRoom) {
  for (const RoomKind kind : {RoomKind::kOffice, RoomKind::kStudentRoom}) {
    BuildingOptions options;
    options.room_kind = kind;
    options.kitchen_every = 4;
    options.seed = 3;
    const World world = generate(options);
    std::map<int, int> per_room;
    for (const ObjectInstance& o : world.objects) {
      const Room& room = world.room(o.room);
      const Rect f = footprintOf(o);
      EXPECT_TRUE(room.footprint.contains(f.min, 0.09) && room.footprint.contains(f.max, 0.09))
          << "object " << o.id << " leaves room " << room.id;
      const Eigen::Vector3d p = o.T_world_object.translation();
      const double z0 = world.floors.at(static_cast<size_t>(room.floor)).z;
      EXPECT_GE(p.z() - 0.5 * o.size.z(), z0 - 1e-9);
      ++per_room[o.room];
      // Nothing stands in the door zone: the first metre behind the door wall.
      const Eigen::Isometry3d T_room_object = roomFrame(world, room).inverse() * o.T_world_object;
      const Rect local = [&] {
        Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e9), hi = -lo;
        for (const double sx : {-0.5, 0.5}) {
          for (const double sy : {-0.5, 0.5}) {
            const Eigen::Vector3d c =
                T_room_object * Eigen::Vector3d(sx * o.size.x(), sy * o.size.y(), 0);
            lo = lo.cwiseMin(c.head<2>());
            hi = hi.cwiseMax(c.head<2>());
          }
        }
        return Rect{lo, hi};
      }();
      EXPECT_GE(local.min.y(), -0.5 * options.room_depth + 1.0 - 1e-9)
          << "object " << o.id << " blocks the door";
      // The same in world terms, whatever the frame: the footprint keeps 1 m from its door.
      for (const Door& door : world.doors) {
        if (door.room_b != room.id) continue;
        const double door_to_box =
            std::max({f.min.y() - door.center.y(), door.center.y() - f.max.y(), 0.0});
        EXPECT_GE(door_to_box, 1.0 - 1e-6) << "object " << o.id << " stands in front of its door";
      }
    }
    // Objects on the floor do not overlap (stacked ones share their base's footprint).
    for (const ObjectInstance& a : world.objects) {
      for (const ObjectInstance& b : world.objects) {
        const bool a_on_floor =
            std::abs(a.T_world_object.translation().z() - 0.5 * a.size.z()) < 1e-9;
        const bool b_on_floor =
            std::abs(b.T_world_object.translation().z() - 0.5 * b.size.z()) < 1e-9;
        if (a.id < b.id && a.room == b.room && a_on_floor && b_on_floor) {
          EXPECT_FALSE(footprintOf(a).overlaps(footprintOf(b))) << a.id << " and " << b.id;
        }
      }
    }
    for (const Room& room : world.rooms) {
      if (room.kind != RoomKind::kCorridor) {
        EXPECT_GE(per_room[room.id], 4) << roomKindName(room.kind);
      }
    }
  }
}

// With identical rooms every room of a kind holds the same furniture at the same place in its own
// frame; without, rooms differ.
TEST(BuildingGenerator, IdenticalRoomsForAliasing) {
  BuildingOptions options;
  options.room_kind = RoomKind::kStudentRoom;
  options.identical_rooms = true;
  const World world = generate(options);
  std::map<int, std::vector<std::pair<uint32_t, Eigen::Matrix4d>>> local;
  for (const ObjectInstance& o : world.objects) {
    const Room& room = world.room(o.room);
    local[o.room].push_back(
        {o.label, (roomFrame(world, room).inverse() * o.T_world_object).matrix()});
  }
  ASSERT_EQ(local.size(), 12u);
  const auto& first = local.begin()->second;
  for (const auto& [room, objects] : local) {
    ASSERT_EQ(objects.size(), first.size()) << room;
    for (size_t i = 0; i < objects.size(); ++i) {
      EXPECT_EQ(objects[i].first, first[i].first);
      EXPECT_LT((objects[i].second - first[i].second).norm(), 1e-9);
    }
  }
  options.identical_rooms = false;
  const World varied = generate(options);
  EXPECT_NE(varied.objects[0].T_world_object.translation().x() -
                varied.room(varied.objects[0].room).footprint.center().x(),
            varied.objects[first.size()].T_world_object.translation().x() -
                varied.room(varied.objects[first.size()].room).footprint.center().x());
}

// Kitchens at drawn slots: as many as asked on every floor, not at a fixed period, the same for
// the same seed, each furnished its own way, and the student rooms still identical to each other.
TEST(BuildingGenerator, RandomKitchensBreakThePeriod) {
  BuildingOptions options;
  options.room_kind = RoomKind::kStudentRoom;
  options.identical_rooms = true;
  options.rooms_per_side = 12;
  options.random_kitchens = 3;
  const auto kitchenSlots = [](const World& world) {
    std::vector<double> x;
    for (const Room& room : world.rooms) {
      if (room.kind == RoomKind::kKitchen) x.push_back(room.footprint.center().x());
    }
    return x;
  };
  const World world = generate(options);
  const std::vector<double> slots = kitchenSlots(world);
  EXPECT_EQ(slots, kitchenSlots(generate(options)));
  ASSERT_EQ(slots.size(), 3u);
  size_t students = 0;
  for (const Room& room : world.rooms) students += room.kind == RoomKind::kStudentRoom;
  EXPECT_EQ(students, 24u - 3u);
  // Each kitchen its own furniture and texture (no shared layout id), each student room the one.
  std::map<int, std::vector<std::pair<uint32_t, Eigen::Vector3d>>> kitchen_furniture;
  for (const Room& room : world.rooms) {
    if (room.kind == RoomKind::kKitchen) {
      EXPECT_EQ(room.layout, -1);
    }
    if (room.kind == RoomKind::kStudentRoom) {
      EXPECT_EQ(room.layout, static_cast<int>(RoomKind::kStudentRoom));
    }
  }
  for (const ObjectInstance& o : world.objects) {
    const Room& room = world.room(o.room);
    if (room.kind == RoomKind::kKitchen)
      kitchen_furniture[o.room].push_back(
          {o.label, (roomFrame(world, room).inverse() * o.T_world_object).translation()});
  }
  ASSERT_EQ(kitchen_furniture.size(), 3u);
  const auto& k0 = kitchen_furniture.begin()->second;
  const auto& k1 = std::next(kitchen_furniture.begin())->second;
  ASSERT_FALSE(k0.empty());
  ASSERT_FALSE(k1.empty());
  EXPECT_GT((k0.front().second - k1.front().second).norm(), 1e-6);
  options.seed = 2;
  EXPECT_NE(slots, kitchenSlots(generate(options)));
  // Without them, no random draw: the building is the one it always was.
  options.random_kitchens = 0;
  options.seed = 1;
  const World plain = generate(options);
  EXPECT_TRUE(kitchenSlots(plain).empty());
  options.random_kitchens = 13;
  auto bad = generateBuilding(options);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "building: random_kitchens must be 0 to rooms_per_side");
}

TEST(BuildingGenerator, FloorsStackAndOptionsAreChecked) {
  BuildingOptions options;
  options.floors = 3;
  const World world = generate(options);
  ASSERT_EQ(world.floors.size(), 3u);
  EXPECT_NEAR(world.floors[2].z, 2 * (options.floor_height + 0.3), 1e-12);
  EXPECT_EQ(world.rooms.size(), 3u * 13u);
  options.room_width = 1.0;
  auto bad = generateBuilding(options);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "building: room_width must be 2.5 to 30 m");
}

}  // namespace
}  // namespace hydra_multi::sim
