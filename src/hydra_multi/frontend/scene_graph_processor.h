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
// Order and integrity, per robot, by sequence number:
//   - the expected sequence is applied; a snapshot (is_snapshot) at or after it replaces all the
//     robot had (and is the way back after a gap);
//   - a later sequence that is not a snapshot waits in a small reorder buffer until the missing
//     ones arrive; if the buffer overflows the robot waits for a snapshot (a gap);
//   - an earlier sequence is a duplicate when its content matches what was applied (ignored), and
//     an error otherwise;
//   - a malformed update (bad numbers, foreign ids, references to nodes that do not exist, a mesh
//     that does not fit) is rejected whole.
// Nothing that is rejected or ignored changes the graph; every such event is logged with the
// robot and the sequence number.
//
// Each robot's mesh, pose graph (odometry and its own loop closures), deformation graph and
// keyframe descriptors are kept beside the graph, per robot, in station ids.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi {

struct ProcessorOptions {
  size_t reorder_buffer = 16;      ///< updates a robot may send ahead of a missing one
  size_t remembered_digests = 64;  ///< applied updates remembered to recognise duplicates
};

enum class UpdateOutcome {
  kApplied,    ///< applied (with any buffered successors it released)
  kBuffered,   ///< ahead of a missing sequence: kept until the gap fills
  kDuplicate,  ///< already applied, same content: ignored
  kWaiting,    ///< the robot has a gap: waiting for a snapshot, update dropped
  kRejected,   ///< malformed or conflicting: dropped
};
const char* updateOutcomeName(UpdateOutcome outcome);

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
  uint64_t next_sequence = 0;
  bool waiting_for_snapshot = false;
  int64_t last_time_ns = 0;
  uint32_t provided_layers = 0;
  size_t updates_applied = 0;
  Mesh mesh;                                 ///< the robot's mesh, in its own frame and indexing
  std::vector<PoseGraphEdge> pose_graph;     ///< station ids
  std::vector<ControlPoint> control_points;  ///< keyframe in station ids
  std::vector<ControlPointEdge> control_point_edges;
  std::map<NodeId, KeyframeDescriptor> descriptors;  ///< by keyframe station id
  RobotId frame;  ///< the frame its nodes are in: its own until the backend aligns it
};

class SceneGraphProcessor {
 public:
  using Logger = std::function<void(const std::string&)>;

  explicit SceneGraphProcessor(ProcessorOptions options = {}, Logger log = {});

  UpdateReport process(const RobotUpdate& update);

  const SceneGraph& graph() const { return graph_; }
  const RobotFrontendState* robot(RobotId robot) const;
  std::vector<RobotId> robots() const;
  /// Updates of a robot held in the reorder buffer, ahead of its missing next_sequence.
  size_t heldBack(RobotId robot) const;

  /// The station id of a robot's node id, and back.
  static std::optional<NodeId> toStation(RobotId robot, NodeId robot_side);
  static std::optional<std::pair<RobotId, NodeId>> toRobotSide(NodeId station);

  /// The frame a node is in (its robot's, until the backend has aligned that robot).
  std::optional<RobotId> frameOf(NodeId station) const;

  /// Counters over every call: the outcome of each arrival, and the buffered updates applied
  /// later, once the one they waited for came (applied + applied_from_buffer were applied).
  struct Counts {
    size_t applied = 0, buffered = 0, duplicates = 0, waiting = 0, rejected = 0;
    size_t applied_from_buffer = 0;
  };
  const Counts& counts() const { return counts_; }

 private:
  struct RobotSlot {
    RobotFrontendState state;
    std::map<uint64_t, RobotUpdate> buffer;  // sequence -> update, ahead of next_sequence
    std::map<uint64_t, size_t> digests;      // sequence -> digest of the applied update
  };

  UpdateReport finish(UpdateReport report);
  Status apply(RobotSlot& slot, const RobotUpdate& update, UpdateReport& report);

  ProcessorOptions options_;
  Logger log_;
  SceneGraph graph_;
  std::map<RobotId, RobotSlot> robots_;
  Counts counts_;
};

}  // namespace hydra_multi
