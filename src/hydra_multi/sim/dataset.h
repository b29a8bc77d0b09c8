#pragma once
// A simulated dataset: generating it from a configuration (presets.h) and writing it.
//
//   DIR/dataset.json               preset, seed, team, sensor profiles and every parameter
//   DIR/robots/<r>/updates.dsgb    robot r's update stream (what the station reads)
//   DIR/gt/                        ground truth, which only evaluation reads:
//     trajectories/<r>.tum         true keyframe poses (TUM: t x y z qx qy qz qw, world frame)
//     start_poses.json             every robot's true start pose in the world frame
//     objects.json                 true objects: label, name, room, centre, size, yaw
//     gvd.json                     free-space GVD voxel centres (the places metric)
//     rooms.json                   floors, rooms and the free cells of every room (rooms metric)
//     loop_closures.json           every intra-robot loop closure, labelled correct or not
// Robot r's directory is named by its letter (a, b, ...), as its agent node ids are.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/graph_summary.h"
#include "hydra_multi/sim/presets.h"

namespace hydra_multi::sim {

struct SimulatedDataset {
  SimulationConfig config;
  std::unique_ptr<SensedWorld> sensed;
  std::vector<RobotPlan> plans;
  std::vector<RobotRun> runs;
  std::vector<std::vector<RobotUpdate>> streams;  ///< one per robot
};

/// Called with a line of progress (what is being done).
using ProgressCallback = std::function<void(const std::string&)>;

/// The world, the team's plans and every robot's true run (trajectory, odometry, loop closures).
Result<SimulatedDataset> planDataset(const SimulationConfig& config,
                                     const ProgressCallback& progress = {});
/// Every robot's update stream (robots in parallel).
void mapDataset(SimulatedDataset& dataset, const ProgressCallback& progress = {});
/// planDataset, then mapDataset.
Result<SimulatedDataset> simulateDataset(const SimulationConfig& config,
                                         const ProgressCallback& progress = {});

/// What each robot did and sent.
struct RobotRunSummary {
  RobotId robot;
  std::string sensor;
  size_t keyframes = 0;
  double path_length_m = 0.0;
  double final_drift_m = 0.0;  ///< odometric end position against the true one, start-aligned
  double final_drift_pct = 0.0;
  GraphSummary graph;  ///< of the robot's final graph
  size_t loop_closures = 0, wrong_loop_closures = 0;
  size_t updates = 0;
  size_t bytes = 0;  ///< of its encoded update stream
};

/// Replays every stream into the robot's graph (checking each update) and summarizes it.
Result<std::vector<RobotRunSummary>> summarizeDataset(const SimulatedDataset& dataset);

/// Writes the dataset into `dir`: a new or empty folder, or one that holds an earlier dataset
/// (replaced); a folder with other files is refused.
Status writeDataset(const SimulatedDataset& dataset, const std::string& dir);

}  // namespace hydra_multi::sim
