#include "hydra_multi/sim/presets.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace hydra_multi::sim {

const char* teamPlanName(TeamPlan plan) {
  switch (plan) {
    case TeamPlan::kOverlapping:
      return "overlapping";
    case TeamPlan::kMeet:
      return "meet";
    case TeamPlan::kFloors:
      return "floors";
  }
  return "overlapping";
}

std::vector<std::string> presetNames() {
  return {"office-3", "residence-3f", "dorm-2", "dorm-2-meet", "hetero-2", "tiny"};
}

Result<SimulationConfig> presetConfig(const std::string& name, uint64_t seed,
                                      std::optional<int> robots, double scale) {
  SimulationConfig c;
  c.preset = name;
  c.seed = seed;
  c.scale = scale;
  BuildingOptions& b = c.building;
  int team = 2;
  if (name == "office-3") {
    team = 3;
    b.rooms_per_side = 9;
    b.room_width = 4.3;
    b.room_depth = 6.0;
    b.corridor_width = 2.4;
    b.open_spaces = 2;
    b.far_side_depth = 18.0;
    b.kitchen_every = 5;
    b.room_kind = RoomKind::kOffice;
    c.plan = TeamPlan::kOverlapping;
    c.coverage = 0.6;
    c.object_threshold_m = 1.0;
  } else if (name == "residence-3f") {
    b.floors = 3;
    b.rooms_per_side = 6;
    b.room_width = 3.6;
    b.room_depth = 4.5;
    b.room_kind = RoomKind::kStudentRoom;
    b.kitchen_every = 4;
    c.plan = TeamPlan::kFloors;
    c.coverage = 0.6;
    c.object_threshold_m = 3.0;
  } else if (name == "dorm-2" || name == "dorm-2-meet" || name == "hetero-2") {
    b.rooms_per_side = 18;
    b.room_width = 3.4;
    b.room_depth = 4.5;
    b.room_kind = RoomKind::kStudentRoom;
    b.identical_rooms = true;
    b.random_kitchens = 3;
    c.plan = name == "dorm-2" ? TeamPlan::kOverlapping : TeamPlan::kMeet;
    c.coverage = 0.8;
    c.object_threshold_m = 2.0;
  } else if (name == "tiny") {
    b.rooms_per_side = 2;
    b.room_width = 4.0;
    b.room_depth = 4.5;
    c.plan = TeamPlan::kOverlapping;
    c.coverage = 0.75;
    c.return_to_start = false;
    c.object_threshold_m = 1.0;
  } else {
    std::string known;
    for (const std::string& n : presetNames()) known += (known.empty() ? "" : ", ") + n;
    return Error{"unknown preset '" + name + "' (known: " + known + ")"};
  }
  if (robots && (*robots < 1 || *robots > 20))
    return Error{"robots must be 1 to 20, not " + std::to_string(*robots)};
  if (!(scale >= 0.25 && scale <= 4.0))
    return Error{"scale must be 0.25 to 4, not " + std::to_string(scale)};
  c.robots = robots.value_or(team);
  b.rooms_per_side = std::max(2, static_cast<int>(std::lround(b.rooms_per_side * scale)));
  if (b.open_spaces > 0)
    b.open_spaces =
        std::clamp(static_cast<int>(std::lround(b.open_spaces * scale)), 1, b.rooms_per_side);
  b.seed = seed;
  c.textures.seed = seed * 31 + 1;
  c.loop_closures.seed = seed * 31 + 2;
  c.mapper.seed = seed * 31 + 3;
  c.mapper.detection.seed = seed * 31 + 4;
  c.odometry.seed = seed * 31 + 5;
  for (int r = 0; r < c.robots; ++r)
    c.sensors.push_back(name == "hetero-2" && r == 1 ? lidarProfile() : rgbdProfile());
  return c;
}

namespace {

// The rooms robots visit, in order along the building: by floor, then along the corridor.
std::vector<int> visitableRooms(const World& world, int floor) {
  std::vector<int> rooms;
  for (const Room& room : world.rooms) {
    if (room.floor == floor && room.kind != RoomKind::kCorridor &&
        room.kind != RoomKind::kStairwell)
      rooms.push_back(room.id);
  }
  std::sort(rooms.begin(), rooms.end(), [&](int a, int b) {
    const double xa = world.room(a).footprint.center().x(),
                 xb = world.room(b).footprint.center().x();
    return xa < xb || (xa == xb && a < b);
  });
  return rooms;
}

// Window `i` of `count` over n items, each `length` long, spread evenly.
std::vector<int> window(const std::vector<int>& items, int i, int count, double coverage) {
  const int n = static_cast<int>(items.size());
  const int length = std::clamp(static_cast<int>(std::ceil(coverage * n)), 1, n);
  const int start =
      count <= 1 ? 0 : static_cast<int>(std::lround(double(i) * (n - length) / (count - 1)));
  return {items.begin() + start, items.begin() + start + length};
}

}  // namespace

Result<std::vector<RobotPlan>> planTeam(const World& world, const FreeSpace& space,
                                        const SimulationConfig& config) {
  std::vector<RobotPlan> plans(static_cast<size_t>(config.robots));
  const int floors = static_cast<int>(world.floors.size());
  for (int r = 0; r < config.robots; ++r) {
    RobotPlan& plan = plans[static_cast<size_t>(r)];
    if (config.plan == TeamPlan::kFloors && floors > 1) {
      // Start on a floor of its own (spread from the bottom to the top), explore it, then a
      // window of the middle floor.
      const int start_floor =
          config.robots <= 1
              ? 0
              : static_cast<int>(std::lround(double(r) * (floors - 1) / (config.robots - 1)));
      const int middle = floors / 2;
      plan.start_floor = start_floor;
      if (start_floor != middle) plan.rooms = visitableRooms(world, start_floor);
      const auto shared = window(visitableRooms(world, middle), r, config.robots, config.coverage);
      plan.rooms.insert(plan.rooms.end(), shared.begin(), shared.end());
    } else {
      const std::vector<int> rooms = visitableRooms(world, 0);
      plan.rooms = window(rooms, r, config.robots, config.coverage);
      if (config.plan == TeamPlan::kMeet && r == 1) {
        // From the far end towards the middle.
        plan.rooms = window(rooms, config.robots - 1, config.robots, config.coverage);
        std::reverse(plan.rooms.begin(), plan.rooms.end());
      } else if (config.plan == TeamPlan::kMeet && r == config.robots - 1 && r > 1) {
        plan.rooms = window(rooms, 1, config.robots, config.coverage);
      }
    }
    if (plan.rooms.empty()) return Error{"team plan: robot " + std::to_string(r) + " has no rooms"};
    if (config.return_to_start && plan.rooms.size() > 1) plan.rooms.push_back(plan.rooms.front());
    const Room& first = world.room(plan.rooms.front());
    plan.start_floor = first.floor;
    // Where a robot can stand in its first room and still drive out: reachable from the
    // corridor.
    const FloorGrid& grid = space.floors.at(static_cast<size_t>(first.floor));
    int corridor = -1;
    for (const Room& room : world.rooms) {
      if (room.floor == first.floor && room.kind == RoomKind::kCorridor) corridor = room.id;
    }
    auto hall = roomStandpoint(grid, corridor);
    if (!hall) return Error{"team plan: " + hall.error()};
    auto start = roomStandpoint(grid, first.id, hall.value(), config.planner.robot_radius);
    if (!start) return Error{"team plan: robot " + std::to_string(r) + ": " + start.error()};
    plan.start = start.value();
  }
  return plans;
}

}  // namespace hydra_multi::sim
