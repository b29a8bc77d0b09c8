#pragma once
// Scoring a scene graph against a simulated dataset's ground truth (DESIGN.md "Metrics"):
//   ATE      over every agent (keyframe) node, matched to its robot's true keyframe by time,
//            after an SE(3) Umeyama alignment;
//   objects  % found / % correct at the dataset's threshold (1 m office, 2 m dorm, 3 m
//            residence);
//   places   mean distance to the nearest true GVD voxel;
//   rooms    precision / recall over free-space cells: an estimated room holds the true free
//            cells inside the free-space spheres of its child places.
// The graph is in the global frame, which is robot 0's odometric frame. Objects, places and rooms
// are scored after the SE(3) fit of the graph's keyframes to their true poses (the ATE's
// alignment), as the paper registers its ground truth to the first robot's frame by ICP of the
// meshes; without 3 matched keyframes, the true start pose of the robot whose frame the graph is
// in (robot 0's unless told) places the graph instead.

#include <optional>
#include <string>
#include <unordered_map>

#include "hydra_multi/eval/dataset_ground_truth.h"
#include "hydra_multi/eval/trajectory_error.h"

namespace hydra_multi {

/// One estimated object as scored: its node, label and world position, and its verdict.
struct ScoredObject {
  NodeId id;
  uint32_t label = 0;
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();
  ObjectVerdict verdict;
};

/// One keyframe as scored: its node, its position (after the fit) and its true position.
struct ScoredKeyframe {
  NodeId id;
  int64_t stamp_ns = 0;
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d true_position = Eigen::Vector3d::Zero();
};

struct SceneGraphScore {
  std::optional<double> ate_rmse_m;  ///< none with fewer than 3 matched keyframes
  std::optional<double> objects_found_pct, objects_correct_pct;
  double object_threshold_m = 1.0;
  std::optional<double> places_position_error_m;
  std::optional<double> rooms_precision, rooms_recall;
  size_t num_objects = 0, num_places = 0, num_rooms = 0;
  /// The estimated objects by verdict (scene_metrics.h): correct (of them duplicates), wrong
  /// label, misplaced.
  size_t objects_correct = 0, objects_duplicates = 0, objects_wrong_label = 0,
         objects_misplaced = 0;
  std::vector<ScoredObject> objects;      ///< every estimated object, in the graph's order
  std::vector<ScoredKeyframe> keyframes;  ///< every keyframe with a true pose, in the graph's order
  size_t matched_keyframes = 0;
  bool aligned_by_trajectory = false;  ///< false: placed by robot 0's true start pose
};

/// The ATE of a graph's keyframes (those the truth has a pose for, matched by robot and time)
/// against their true positions, and with `keyframes` those keyframes, positions as in the graph;
/// an error with fewer than 3 matched.
Result<TrajectoryError> keyframeTrajectoryError(const SceneGraph& graph,
                                                const DatasetGroundTruth& truth,
                                                std::vector<ScoredKeyframe>* keyframes = nullptr);

/// `global_robot`: the robot whose frame the graph is in (StationResult::global_robot), used only
/// without 3 matched keyframes; by default the team's first.
SceneGraphScore evaluateSceneGraph(const SceneGraph& graph, const DatasetGroundTruth& truth,
                                   std::optional<RobotId> global_robot = std::nullopt);

/// Every robot's graph in one graph in the global frame, robot r moved by T_global_r (node ids
/// remapped to station ids naming their robot; mesh vertices appended).
SceneGraph combineRobotGraphs(const std::vector<std::pair<RobotId, SceneGraph>>& graphs,
                              const std::map<RobotId, Eigen::Isometry3d>& T_global_robot);

/// Whether a loop closure between two robots' keyframes (given by their timestamps) is right:
/// its relative pose T_a_b within max_translation_m and max_rotation_deg of the true one.
struct LoopClosureCheck {
  bool known = false;  ///< both keyframes found in the ground truth
  bool correct = false;
  double translation_error_m = 0.0, rotation_error_deg = 0.0;
};
LoopClosureCheck checkLoopClosure(const DatasetGroundTruth& truth, RobotId robot_a, int64_t stamp_a,
                                  RobotId robot_b, int64_t stamp_b, const Eigen::Isometry3d& T_a_b,
                                  double max_translation_m = 1.0, double max_rotation_deg = 10.0);

/// One side of a merge: the node's position and a keyframe of the node's robot near it (its stamp
/// and pose), both in one frame: best the robot's own, as it mapped them (backend.h).
struct MergeSide {
  RobotId robot;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  int64_t keyframe_stamp_ns = -1;
  Eigen::Isometry3d T_robot_keyframe = Eigen::Isometry3d::Identity();
};

/// Where two merged nodes truly are: each placed relative to its keyframe's true pose (so the
/// frame's errors cancel), then their true rooms. A merge is across rooms when both lie
/// in rooms, the rooms differ and the true positions are more than min_distance_m apart (two
/// sides of a doorway are not two rooms merged).
struct MergeCheck {
  bool checked = false;  ///< both keyframes have a true pose
  bool across_rooms = false;
  double true_distance_m = 0.0;
  int room_a = -1, room_b = -1;  ///< true room ids of the two nodes (-1: outside every room)
};
/// The true room of every free cell of a dataset, indexed once for many look-ups.
class TrueRooms {
 public:
  explicit TrueRooms(const DatasetGroundTruth& truth);
  const DatasetGroundTruth& truth() const { return *truth_; }
  /// The true room id at a world position (-1: outside every room).
  int at(const Eigen::Vector3d& p) const;
  /// Whether the cell (x, y) of a floor's grid lies in a room.
  bool inRoom(int x, int y, int floor) const;

 private:
  const DatasetGroundTruth* truth_;
  std::unordered_map<int64_t, int> room_of_cell_;
};
MergeCheck checkMerge(const TrueRooms& rooms, const MergeSide& a, const MergeSide& b,
                      double min_distance_m = 1.0);

/// What makes a dataset hard, measured on its files:
struct DatasetDifficulty {
  /// Of the `top_pairs` inter-robot keyframe pairs with the highest bag-of-words similarity
  /// (both keyframes inside a true room, not a corridor or stairwell), the share in different
  /// true rooms.
  size_t top_pairs = 0;
  double aliased_pct = 0.0;
  double top_similarity_mean = 0.0;  ///< their mean similarity (1: identical views)
  /// The robots' own graphs placed with the true start poses (odometry alone, no loop
  /// closures), and the same objects placed without drift (each corrected by its robot's true
  /// pose when it was first sent): how much the drift costs.
  SceneGraphScore odometry, no_drift;
  double object_threshold_m = 1.0;
};
Result<DatasetDifficulty> measureDatasetDifficulty(const std::string& dir, size_t top_pairs = 100);

}  // namespace hydra_multi
