#pragma once
// Presets: a building, a team and every parameter of a simulated dataset, deterministic from the
// seed (issue 4; the paper's Section IV-A datasets they imitate in brackets):
//   office-3      one office floor of about 40 x 27 m: offices, two open spaces, a kitchen;
//                 3 RGB-D robots exploring different but overlapping parts (uHumans2)
//   residence-3f  three floors joined by stairs; 2 robots starting on the top and bottom floors,
//                 both exploring the middle one (SidPac)
//   dorm-2        a long floor of identical student rooms and 3 kitchens, each its own, at slots
//                 drawn from the seed; 2 robots starting in different rooms, going the same way
//                 (Simmons 1)
//   dorm-2-meet   the same building, robots starting at opposite ends, meeting in the middle
//                 (Simmons 2)
//   hetero-2      dorm-2-meet with robot 1 a lidar robot: no labels, no objects
//   tiny          four rooms and 2 robots, for tests
// `robots` and `scale` change the team size and the number of rooms along the corridor.

#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/exploration.h"
#include "hydra_multi/sim/free_space.h"
#include "hydra_multi/sim/loop_closures.h"
#include "hydra_multi/sim/robot_mapper.h"
#include "hydra_multi/sim/surfaces.h"
#include "hydra_multi/sim/textures.h"
#include "hydra_multi/sim/trajectory.h"

namespace hydra_multi::sim {

/// How a team splits a building.
enum class TeamPlan {
  kOverlapping,  ///< windows of rooms along the building, overlapping, all the same way
  kMeet,         ///< robots 0 and 1 start at opposite ends and meet in the middle
  kFloors,       ///< robots start on different floors and all explore the middle floor
};
const char* teamPlanName(TeamPlan plan);

struct SimulationConfig {
  std::string preset;
  uint64_t seed = 1;
  int robots = 2;
  double scale = 1.0;
  TeamPlan plan = TeamPlan::kOverlapping;
  double coverage = 0.6;        ///< kOverlapping/kMeet: share of the rooms each robot visits
  bool return_to_start = true;  ///< robots end their tour back in their start room
  double robot_start_interval_s = 2.0;  ///< robot r starts r times this after robot 0
  double object_threshold_m = 1.0;      ///< the objects metric's distance for this building
  std::vector<SensorProfile> sensors;   ///< one per robot
  BuildingOptions building;
  FreeSpaceOptions free_space;
  SurfaceOptions surfaces;
  TextureOptions textures;
  PathPlannerOptions planner;
  TrajectoryOptions trajectory;
  OdometryNoise odometry;  ///< seed: per robot, derived from `seed`
  LoopClosureOptions loop_closures;
  MapperOptions mapper;
};

std::vector<std::string> presetNames();

/// The configuration of a preset; `robots` (1 to 20) and `scale` (0.25 to 4) override its team
/// size and building length. An unknown name or a bad number is an error that says which.
Result<SimulationConfig> presetConfig(const std::string& name, uint64_t seed,
                                      std::optional<int> robots = std::nullopt, double scale = 1.0);

/// Where a robot starts and which rooms it visits, in order.
struct RobotPlan {
  int start_floor = 0;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  std::vector<int> rooms;
};

/// The team's plans in a generated world.
Result<std::vector<RobotPlan>> planTeam(const World& world, const FreeSpace& space,
                                        const SimulationConfig& config);

}  // namespace hydra_multi::sim
