#pragma once
// HydraGraphInput: a Hydra robot's whole scene graphs (Spark-DSG's ZmqSink sends one after every
// backend update, ../shared/reference/spark-dsg-wire.md §3) turned into the robot updates the
// station takes (dsg/robot_update.h). Each graph becomes the difference to the last one taken:
// nodes and edges added, changed and removed, the mesh from its first changed vertex and face.
// What Hydra does not send is derived from the graph:
//   pose graph      odometry between consecutive keyframes (by index) of the robot's agents,
//                   T_from_to = T_from^-1 T_to from their poses, with fixed variances;
//   control points  the deformation graph of our robots: the first mesh vertex in every new
//                   control_point_spacing voxel, attached to the keyframe of its stamp (the last
//                   one at or before it; without stamps the nearest), joined to the points of
//                   the 26 neighbouring voxels;
//   descriptors     each keyframe's bag of words from its agent's dbow_ids and dbow_values; no
//                   keypoints (Hydra sends none), so visual loop closures are not verified.
// Identity: the robot is the one the station was told; its agents are re-keyed to that robot's
// prefix whatever prefix they carry (every Hydra robot started as robot 0 uses 'a'). Frontiers
// (places that are not real) and layers the station has no place for are left out and counted.
// The first graph, the first after resumeAt(), and any graph in which the robot corrected what it
// had sent (a keyframe pair's relative pose moved, a keyframe vanished, mesh vertices sent before
// changed) go whole, as a snapshot with everything derived anew; the rest go as deltas.
// A graph that cannot be used is an error and changes nothing: the next is taken against the
// last good one, so nothing the station had is lost.

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct HydraInputOptions {
  double control_point_spacing = 2.5;  ///< deformation-graph voxel (m), as our robots'
  /// Information of the derived odometry: variances of translation (m^2) and rotation (rad^2).
  double odometry_translation_variance = 1e-2, odometry_rotation_variance = 1e-4;
  /// A keyframe pair whose relative pose moved more than this since its odometry was sent is a
  /// correction by the robot (m, rad): the update goes whole.
  double correction_translation_m = 1e-6, correction_rotation_rad = 1e-6;

  /// Empty when usable, else what is wrong.
  std::string invalid() const;
};

/// What taking one graph noticed, besides the update.
struct HydraGraphNotes {
  std::map<std::string, size_t> left_out;  ///< "frontiers (places not real)" -> count, ...
  std::optional<char> agent_prefix;        ///< the prefix the agents carried, when not the robot's
  size_t bow_refused = 0;                  ///< agents whose dbow_ids and dbow_values disagree
  std::string correction;  ///< why the update went whole, when it did after the first
};

class HydraGraphInput {
 public:
  explicit HydraGraphInput(RobotId robot, HydraInputOptions options = {});

  /// The update that brings the station from the last graph taken to this one; nullopt when
  /// nothing changed. `notes` (optional) receives what was noticed.
  Result<std::optional<RobotUpdate>> take(const io::spark::Graph& graph,
                                          HydraGraphNotes* notes = nullptr);

  /// The station holds this robot's updates before `next_sequence` (a station restarted on its
  /// journal): the next graph goes whole, numbered `next_sequence`.
  void resumeAt(uint64_t next_sequence);

  RobotId robot() const { return robot_; }
  uint64_t nextSequence() const { return next_sequence_; }
  /// The robot's graph as last taken (robot-side ids, agents under the robot's prefix).
  const SceneGraph& graph() const { return graph_; }

 private:
  using Voxel = std::tuple<int, int, int>;
  struct Derived {
    std::vector<PoseGraphEdge> pose_graph;
    DeformationGraphDelta deformation;
    std::vector<KeyframeDescriptor> descriptors;
  };

  void resetDerived();
  Derived derive(const SceneGraph& graph, const std::map<NodeId, std::vector<BowEntry>>& bow,
                 size_t first_vertex);
  /// Why the robot's new graph changes what was derived from the last one ("" when it does not).
  std::string correctionOf(const SceneGraph& graph) const;

  RobotId robot_;
  HydraInputOptions options_;
  uint64_t next_sequence_ = 0;
  bool whole_next_ = true;
  int64_t time_ns_ = 0;
  SceneGraph graph_;
  // What was derived and sent so far.
  std::vector<NodeId> chain_;  // keyframes joined by odometry, in order
  std::map<NodeId, Eigen::Isometry3d> chain_poses_;
  std::map<Voxel, uint64_t> voxels_;
  size_t vertices_scanned_ = 0;
  std::map<NodeId, std::vector<BowEntry>> bow_sent_;
};

/// The graph a Hydra robot would publish for a robot's map (a snapshot of its updates,
/// dsg/robot_stream.h): its nodes, edges and mesh in Spark-DSG's form (dsg/io/spark_graph.h) with
/// each keyframe's bag of words on its agent; its keypoints, pose graph and deformation graph are
/// not in it, as Hydra sends none.
Result<io::spark::Graph> hydraGraphOfMap(const RobotUpdate& snapshot);

}  // namespace hydra_multi
