#pragma once
// Reading a simulated dataset's ground truth (DIR/gt, written by sim/dataset.h) and the parts of
// the dataset evaluation needs. Only evaluation reads this; the station never does.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/core/se3.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"
#include "hydra_multi/dsg/update_sequencer.h"
#include "hydra_multi/eval/scene_metrics.h"

namespace hydra_multi {

/// A floor's free-space grid: where room cells are.
struct GroundTruthGrid {
  int floor = 0;
  double z = 0.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double resolution = 0.1;
  int width = 0, height = 0;
  Eigen::Vector2i cellOf(const Eigen::Vector2d& p) const;
};

struct DatasetGroundTruth {
  std::string dir;
  double object_threshold_m = 1.0;
  std::vector<RobotId> robots;                       ///< from dataset.json, in order
  std::map<RobotId, std::string> streams;            ///< robot -> update stream path
  std::map<RobotId, Eigen::Isometry3d> start_poses;  ///< T_world_start
  struct Trajectory {
    std::vector<int64_t> stamps_ns;
    std::vector<Eigen::Isometry3d> poses;  ///< T_world_body
  };
  std::map<RobotId, Trajectory> trajectories;
  std::vector<LabelledPoint> objects;  ///< world frame
  std::vector<Eigen::Vector3d> gvd;    ///< world frame
  std::vector<GroundTruthGrid> grids;
  std::vector<int> room_ids;
  std::vector<std::string> room_kinds;  ///< "corridor", "office", ... per room_ids entry
  std::vector<std::vector<Eigen::Vector3i>> room_cells;  ///< (x, y, floor), per room_ids entry

  /// The true pose of a robot's keyframe at this time (within 1 ms); nullptr if none.
  const Eigen::Isometry3d* poseAt(RobotId robot, int64_t stamp_ns) const;
  /// The grid whose floor a point at height z above it belongs to (places and agents sit about
  /// 1 m above their floor); nullptr without grids.
  const GroundTruthGrid* gridFor(double z) const;
  /// T_world_global: the global frame of a result in the world, that of `robot` (by default
  /// the team's first robot, whose frame the station's map is in unless it had no data of it).
  Eigen::Isometry3d worldFromGlobal(std::optional<RobotId> robot = std::nullopt) const;
};

/// Reads DIR/dataset.json and DIR/gt/*; errors name the file and what is wrong.
Result<DatasetGroundTruth> readDatasetGroundTruth(const std::string& dir);

/// One robot's final robot-side graph (its frame): its update stream replayed by the station's
/// order rule (dsg/robot_stream.h), with what became of its updates and records.
struct RobotReplay {
  SceneGraph graph;
  UpdateCounts counts;
  std::vector<std::string> skipped;  ///< damaged records and updates of other robots, named
  std::string summary;               ///< describeStream's line
};
Result<RobotReplay> replayRobotGraph(const DatasetGroundTruth& dataset, RobotId robot);

}  // namespace hydra_multi
