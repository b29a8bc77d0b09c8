#pragma once
// What a robot has sent so far, folded into one snapshot. A robot that sends deltas can send this
// now and then instead (the paper's robots send their whole scene graph every time): a station
// that lost an update, and so waits for a snapshot, recovers with it (frontend/
// scene_graph_processor.h applies a snapshot in place of the robot's whole state).

#include <functional>
#include <map>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/dsg/update_sequencer.h"

namespace hydra_multi {

/// Applies an update's graph to the robot's own graph (robot-side ids) as a replay of its stream
/// does: a snapshot replaces the graph, a delta changes it. On an error nothing changes.
Status applyToRobotGraph(SceneGraph& graph, const RobotUpdate& update);

/// One robot's recorded stream replayed into the robot's own graph (robot-side ids) by the order
/// rule the station applies (update_sequencer.h): a gap holds the later updates back until a
/// snapshot, a malformed update is rejected. What it ends with of the robot, and what it counts,
/// is what the station ends with and counts.
class RobotStreamReplay {
 public:
  using Applied = std::function<void(const RobotUpdate&, const SceneGraph&)>;

  /// `digest`: as the station's (io::robotUpdateDigest), to tell duplicates from conflicts.
  explicit RobotStreamReplay(RobotId robot, UpdateSequencer::Digest digest = {},
                             SequencerOptions options = {})
      : robot_(robot), order_(options, std::move(digest)) {}

  /// The stream's next update, in file order; `applied` is called after each update this applies
  /// (it, and the buffered ones it releases), with the graph as it left it.
  SequencedUpdate add(const RobotUpdate& update, const Applied& applied = {});

  const SceneGraph& graph() const { return graph_; }
  SceneGraph& graph() { return graph_; }
  const UpdateSequencer& order() const { return order_; }

 private:
  RobotId robot_;
  UpdateSequencer order_;
  SceneGraph graph_;
};

class RobotStreamState {
 public:
  /// The robot's next update, in sequence order (a snapshot starts over). Checked as the station
  /// checks it; an update that does not apply is an error naming it, and changes nothing.
  Status add(const RobotUpdate& update);

  /// The snapshot that stands for every update added: the graph and mesh they built, each
  /// pose-graph edge, control point (and edge) and descriptor whose keyframe is still there, and
  /// the last update's robot, sequence, time and layers. Applied where the last update would be,
  /// it leaves the station as the updates did.
  RobotUpdate snapshot() const;

  /// The updates snapshot() stands for: the last snapshot added and those after it (0 before the
  /// first).
  size_t updatesAdded() const { return added_; }

 private:
  RobotUpdate last_;  // header fields only
  SceneGraph graph_;  // robot-side ids, with the robot's mesh
  std::vector<PoseGraphEdge> pose_graph_;
  DeformationGraphDelta deformation_;
  std::map<NodeId, KeyframeDescriptor> descriptors_;
  size_t added_ = 0;
  bool started_ = false;
};

}  // namespace hydra_multi
