#pragma once
// SceneGraphProcessor: the station's frontend graph (paper III-A; DESIGN.md "Data flow"). It takes
// robot updates in arrival order, from any number of robots joining at any time, and keeps one
// scene graph of everything they sent, un-optimized and un-merged, each robot's nodes in that
// robot's own odometric frame.
//
// Ids: a robot's node id X becomes the station id X@robot (NodeId::station), so robots' ids never
// collide and every station id says which robot and which robot-side id it comes from. Agent
// nodes must carry the sending robot's own prefix letter.
//
// Order and integrity, per robot, by sequence number: the order rule of dsg/update_sequencer.h
// (reorder buffer, gaps that wait for a snapshot, duplicates told from conflicting replays), the
// same rule every replay of a recorded stream applies. A malformed update (bad numbers, foreign
// ids, references to nodes that do not exist, a mesh that does not fit) is rejected whole.
// Nothing that is rejected or ignored changes the graph; every such event is logged with the
// robot and the sequence number.
//
// Each robot's mesh, pose graph (odometry and its own loop closures), deformation graph and
// keyframe descriptors are kept beside the graph, per robot, in station ids. Two indexes follow
// the graph as updates apply, for the loop-closure detector: the objects per semantic label, and
// each robot's keyframes by time.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"
#include "hydra_multi/dsg/update_sequencer.h"

namespace hydra_multi {

using ProcessorOptions = SequencerOptions;

/// What one call of process() did.
struct UpdateReport {
  RobotId robot;
  uint64_t sequence = 0;
  UpdateOutcome outcome = UpdateOutcome::kRejected;
  std::string message;                ///< why, for everything but kApplied
  std::vector<uint64_t> applied;      ///< sequence numbers applied by this call, in order
  std::vector<NodeId> new_keyframes;  ///< station ids of keyframes added by this call
  size_t nodes_changed = 0, nodes_removed = 0;
};

/// A robot's state beside the graph.
struct RobotFrontendState {
  int64_t last_time_ns = 0;
  uint32_t provided_layers = 0;
  Mesh mesh;                                 ///< the robot's mesh, in its own frame and indexing
  std::vector<PoseGraphEdge> pose_graph;     ///< station ids
  std::vector<ControlPoint> control_points;  ///< keyframe in station ids
  std::vector<ControlPointEdge> control_point_edges;
  std::map<NodeId, KeyframeDescriptor> descriptors;  ///< by keyframe station id
  RobotId frame;  ///< the frame its nodes are in: its own until the backend aligns it
};

/// What one applied update changed of its robot's state beside the graph (all of
/// RobotFrontendState but the descriptors, which are the detector's), in station ids.
struct RobotStateDelta {
  RobotId robot;
  bool snapshot = false;  ///< the robot's state starts afresh
  MeshDelta mesh;         ///< the robot's own mesh
  std::vector<PoseGraphEdge> pose_graph;
  std::vector<ControlPoint> control_points;
  std::vector<ControlPointEdge> control_point_edges;
  int64_t time_ns = 0;
  uint32_t provided_layers = 0;
};

/// Applies a robot's state delta (the processor's own way of changing that state).
void applyStateDelta(RobotFrontendState& state, const RobotStateDelta& delta);

/// An applied update's changes: to the graph and to its robot's state.
struct AppliedDelta {
  GraphDelta graph;
  RobotStateDelta robot;
};

class SceneGraphProcessor {
 public:
  using Logger = std::function<void(const std::string&)>;

  explicit SceneGraphProcessor(ProcessorOptions options = {}, Logger log = {});

  UpdateReport process(const RobotUpdate& update);

  const SceneGraph& graph() const { return graph_; }
  const RobotFrontendState* robot(RobotId robot) const;
  std::vector<RobotId> robots() const;
  /// A robot's place in its stream: the sequence it expects, whether it waits for a snapshot,
  /// the updates held back, and what became of its updates (nullptr for a robot never heard of).
  const UpdateSequencer* order(RobotId robot) const;
  /// The robots with at least one update applied.
  std::vector<RobotId> robotsWithData() const;

  /// The station id of a robot's node id, and back.
  static std::optional<NodeId> toStation(RobotId robot, NodeId robot_side);
  static std::optional<std::pair<RobotId, NodeId>> toRobotSide(NodeId station);

  /// The frame a node is in (its robot's, until the backend has aligned that robot).
  std::optional<RobotId> frameOf(NodeId station) const;

  /// Per semantic label, how many objects graph() holds (a label with none: no entry).
  const std::map<uint32_t, size_t>& objectsPerLabel() const { return objects_per_label_; }
  /// The robot's keyframe (an agent node with its stamp) whose stamp is nearest `time_ns`; of
  /// several as near, the one with the smallest id. nullopt: the robot has none.
  std::optional<NodeId> keyframeNearest(RobotId robot, int64_t time_ns) const;

  /// What became of every update so far, over all robots; updates refused before a robot could
  /// be told (an invalid robot id) are counted as rejected.
  UpdateCounts counts() const;
  using Counts = UpdateCounts;

  /// Keeps the changes of every update the processor applies from now on (station ids), for
  /// takeDeltas: a copy of graph() and of the robots' states follows it by applying them in order
  /// (applyDelta, applyStateDelta; a robot's state new to the copy starts in its own frame),
  /// without a copy of either.
  void keepDeltas() { keep_deltas_ = true; }
  /// The changes applied since the last call (or keepDeltas), in order, and forgets them.
  std::vector<AppliedDelta> takeDeltas() { return std::exchange(deltas_, {}); }

 private:
  struct RobotSlot {
    RobotFrontendState state;
    UpdateSequencer order;
  };

  RobotSlot& slot(RobotId robot);
  UpdateReport finish(UpdateReport report) const;
  Status apply(RobotSlot& slot, const RobotUpdate& update, UpdateReport& report);
  // Counts graph_'s node `id` in the indexes below (+1) or takes it out of them (-1).
  void index(NodeId id, int sign);

  ProcessorOptions options_;
  Logger log_;
  SceneGraph graph_;
  bool keep_deltas_ = false;
  std::vector<AppliedDelta> deltas_;  // applied since takeDeltas, with keep_deltas_
  std::map<RobotId, RobotSlot> robots_;
  size_t refused_without_robot_ = 0;  // updates whose robot id is not valid
  std::map<uint32_t, size_t> objects_per_label_;
  // Per robot, its keyframes' ids by stamp.
  std::map<RobotId, std::map<int64_t, std::set<NodeId>>> keyframe_times_;
};

}  // namespace hydra_multi
