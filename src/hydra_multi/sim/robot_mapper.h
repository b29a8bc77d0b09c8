#pragma once
// Robot-side mapping emulation: the update stream a robot running Hydra would send (DESIGN.md
// "What a robot sends"), made from what it observes of the world along its true trajectory and
// placed with its drifting odometry. Nothing of the ground truth leaves except through the
// robot's own noisy view of it; everything in the stream is in the robot's odometric frame.
//
// For keyframe k with true pose T_world_k and odometric pose T_odom_k, whatever the robot first
// observes at k is placed with the drift D_k = T_odom_k * T_world_k^-1 (world -> robot frame).
// Per keyframe:
//   agents   the keyframe node (odometric pose), an edge to the previous keyframe, an odometry
//            edge of the pose graph with the information of the odometry noise, and its parent
//            place (the nearest place the robot has);
//   mesh     the world's surface vertices (surfaces.h) that come into sensor range and field of
//            view for the first time and are in line of sight, with noise; a triangle once its
//            three vertices are seen; labels from a semantic sensor only;
//   deformation graph: a control point for every new control_point_spacing voxel of mesh,
//            attached to the keyframe, joined to the control points of neighbouring voxels;
//   places   the places (places.h) first seen from this keyframe, edges once both ends exist;
//   objects  (semantic robots) detections completed at this keyframe (object_detection.h) with
//            their mesh vertices; some large objects are first reported as two halves that are
//            merged later, and some spurious objects appear and are deleted later: the updates
//            carry those node deletions;
//   visual   the keyframe descriptor (textures.h) with depth-dependent keypoint noise;
//   loop closures ending at this keyframe (loop_closures.h).
// An update is flushed every update_period_s of robot time and after the last keyframe; the
// first is marked as a snapshot (it is the whole graph so far), and with snapshot_every so is
// every snapshot_every-th, sent whole (dsg/robot_stream.h).

#include <memory>
#include <string>
#include <vector>

#include "hydra_multi/core/nearest_neighbors.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/sim/loop_closures.h"
#include "hydra_multi/sim/object_detection.h"
#include "hydra_multi/sim/places.h"
#include "hydra_multi/sim/surfaces.h"
#include "hydra_multi/sim/textures.h"

namespace hydra_multi::sim {

/// What a robot's sensors are: a semantic RGB-D camera, or a lidar with a plain camera.
struct SensorProfile {
  std::string kind = "rgbd";  ///< rgbd | lidar
  bool semantic = true;       ///< labelled mesh and objects
  double mesh_range = 5.0;    ///< m
  double mesh_horizontal_fov_deg = 90.0;
  double mesh_vertical_fov_deg = 60.0;
  SensorModel camera;  ///< objects and visual descriptors

  /// The layers a robot with this sensor sends (RobotUpdate::provided_layers).
  uint32_t providedLayers() const;
};
/// An RGB-D camera of about 90 x 60 degrees, depth to 5 m (the range Hydra integrates).
SensorProfile rgbdProfile();
/// A 360-degree lidar (+-15 degrees vertically, as a 16-beam unit) to 10 m, no semantics.
SensorProfile lidarProfile();

struct MapperOptions {
  double update_period_s = 5.0;
  /// Every this many updates the robot sends the snapshot of its whole map instead of a delta,
  /// so a station that lost an update recovers (0: only the first update is a snapshot).
  size_t snapshot_every = 0;
  /// What a robot sends beyond what a Hydra robot's graph holds: its keyframes' keypoints and
  /// its own loop closures. Off, its stream holds only what the station can take from Hydra.
  bool send_keypoints = true;
  bool send_own_loop_closures = true;
  double mesh_noise_sigma = 0.01;      ///< per vertex and axis (m)
  double control_point_spacing = 2.5;  ///< deformation-graph voxel (m; Hydra: 2.5)
  double keypoint_sigma_base = 0.002;  ///< keypoint noise a + b * depth^2 (m), RGB-D-like
  double keypoint_sigma_per_m2 = 0.002;
  double split_probability = 0.15;     ///< of a detection of an object at least 1 m long
  double split_min_extent = 1.0;       ///< m
  double split_merge_delay_s = 20.0;   ///< the halves are merged this much later
  double spurious_probability = 0.05;  ///< per detection: a false object appears beside it
  double spurious_lifetime_s = 10.0;   ///< and is deleted this much later
  double loop_closure_translation_sigma = 0.05;  ///< information of loop-closure edges (m)
  double loop_closure_rotation_sigma_deg = 2.0;
  double parent_place_radius = 3.0;  ///< agents and objects attach to a place this close (m)
  PlacesOptions places;
  DetectionOptions detection;
  uint64_t seed = 1;
};

/// The world as the robots' sensors see it, built once per dataset.
struct SensedWorld {
  World world;
  FreeSpace space;
  WorldMesh mesh;
  std::vector<TexturedPoint> textures;
  std::unique_ptr<NearestNeighbors> mesh_index;     ///< over mesh vertex positions
  std::vector<std::vector<uint32_t>> vertex_faces;  ///< faces of every mesh vertex

  SensedWorld(World world, FreeSpace space, WorldMesh mesh, std::vector<TexturedPoint> textures);
  /// The floor a body pose is on (the highest floor at most half a metre above its feet).
  int floorOf(const Eigen::Vector3d& body_position, double body_height) const;
  /// The true room of a body position (-1 in doorways, on stairs and outside).
  int roomOf(int floor, const Eigen::Vector3d& body_position) const;
};

/// One robot's run: its true keyframes, their floors, its odometry and its loop closures.
struct RobotRun {
  RobotId robot;
  SensorProfile sensor;
  std::vector<StampedPose> truth;
  std::vector<int> floors;
  std::vector<Eigen::Isometry3d> odometry;  ///< robot frame; odometry[0] is the identity
  OdometryNoise odometry_noise;             ///< for the odometry edges' information
  std::vector<SimulatedLoopClosure> loop_closures;
};

/// The robot's update stream, in time order, sequence numbers from 0.
std::vector<RobotUpdate> emulateRobotMap(const SensedWorld& sensed, const RobotRun& run,
                                         const MapperOptions& options = {});

}  // namespace hydra_multi::sim
