#pragma once
// The station (DESIGN.md "Data flow"): one pipeline that any input feeds. `Station::submit` puts a
// robot update on the ingest queue from any thread (the file replay below, later the network);
// the frontend thread takes them in arrival order (or, with `time_order_hold_s`, in robot-time
// order: time_order.h) through the scene-graph processor and the
// loop-closure detector, timed; whenever the backend thread is idle and the frontend has news,
// the frontend hands it what changed of its state since the last hand-off (graph deltas, each
// robot's mesh, pose graph and control points added) with the inter-robot loop closures and goes
// on; the backend thread brings its own copy of the state up to date with them and runs a round
// on it (backend.h). The
// frontend never waits for the backend. `finish` closes the input: the frontend works off the
// queue, the detector describes the remaining keyframes and the backend runs one last round on
// the final state, from scratch (Backend::round), so the final map is the same whenever the
// earlier rounds ran.
// The global frame should be robot a's; each round asks for the first robot with an update applied
// (backend/initial_alignment.h moves the frame to it once it is aligned), so a robot the station
// has nothing of never takes the others with it.
// Log lines come from both threads; the station calls `log` for one line at a time.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hydra_multi/backend/backend.h"
#include "hydra_multi/frontend/loop_closure_detector.h"
#include "hydra_multi/station/dataset_replay.h"
#include "hydra_multi/station/freed_memory.h"

namespace hydra_multi {

struct RoundTiming;

/// A robot's place in the station's input when a backend round's snapshot was taken.
struct RobotProgress {
  size_t applied = 0;          ///< updates applied
  uint64_t next_sequence = 0;  ///< the sequence it expects next
  int64_t robot_time_ns = 0;   ///< the robot time of its latest update applied
};

/// What a backend round gives the station's outputs for others (the fused graph, the viewer).
struct RoundOutput {
  const SceneGraph& graph;  ///< the backend graph, in the global frame
  const RoundTiming& timing;
  const std::vector<LoopClosureVerdict>& loop_closures;
  const std::vector<AcceptedMerge>& merges;
  const std::map<RobotId, RobotFrameAlignment>& aligned;
  const std::map<RobotId, RobotProgress>& progress;  ///< every robot heard of
};

struct StationOptions {
  double speed = 0.0;  ///< file replay: 1 real time, 10 ten times faster, 0 as fast as possible
  /// Above 0: updates put in robot-time order before the frontend, each held at most this long
  /// (time_order.h), so that a network's delivery order does not change the map; 0: arrival order.
  double time_order_hold_s = 0.0;
  /// With the time order: the team's size; until that many robots have sent something, only the
  /// hold releases (0: the robots heard of so far are the team).
  size_t expected_robots = 0;
  /// Freed memory kept for the next backend round, up to this many MB, then all handed back
  /// (freed_memory.h); 0: the allocator's default (freed pages handed back within about 10 s).
  size_t keep_freed_mb = 3072;
  ProcessorOptions processor;
  LoopClosureOptions detector;
  BackendOptions backend;
  std::function<void(const std::string&)> log;  ///< progress and warnings
  /// Called in the backend thread after every round (the station's outputs for others:
  /// net/fused_graph.h publishes it, web/ shows it); must not block for long.
  std::function<void(const RoundOutput&)> on_round;
  /// Evaluation only (the oracle-lc yardstick): the inter-robot loop closures the backend may
  /// see; the frontend's graph gives the keyframes' stamps. Empty: all of them.
  std::function<bool(const DetectedLoopClosure&, const SceneGraph&)> loop_closure_filter;
};

struct UpdateTiming {
  RobotId robot;
  uint64_t sequence = 0;
  int64_t time_ns = 0;
  double frontend_ms = 0.0;  ///< processing and detection
  double queue_ms = 0.0;     ///< waiting on the ingest queue before that
  double handoff_ms = 0.0;   ///< handing the backend what changed (0 when none)
  size_t loop_closures = 0;  ///< found by this update
};

struct RoundTiming {
  size_t round = 0;
  size_t after_update = 0;  ///< updates processed when the round's snapshot was taken
  BackendRoundReport report;
  FreedMemory freed;  ///< after the round: what the allocator held freed, and if handed back
};

struct StationResult {
  SceneGraph graph;  ///< the final backend graph, in global_robot's frame
  std::vector<UpdateTiming> updates;
  std::vector<RoundTiming> rounds;
  std::vector<DetectedLoopClosure> loop_closures;
  std::map<std::pair<NodeId, NodeId>, bool> inter_robot_inliers;  ///< last round's GNC
  std::map<std::pair<NodeId, NodeId>, bool> alignment_inliers;    ///< last round's averaging
  std::vector<AcceptedMerge> merges;                              ///< last round's
  std::map<NodeId, int64_t> keyframe_stamps;  ///< every keyframe the frontend holds at the end
  uint64_t frontend_digest = 0;               ///< of the robots' maps the frontend holds at the end
  std::map<RobotId, RobotFrameAlignment> aligned;
  UpdateCounts counts;
  /// With the time order: per robot, the updates that went on after one later in robot time (its
  /// hold ran out without them); the map may then differ from the replay's.
  std::map<RobotId, size_t> late;
  /// The robot whose frame `graph` is in: robot a's, unless the station had nothing of it when
  /// the map began (then the first robot it had data of, until a is aligned with it).
  RobotId global_robot;
  size_t robots = 0;
  double wall_s = 0.0;
};

class Station {
 public:
  /// Starts the frontend and backend threads. `team`: the robots expected, if known (the first
  /// is the global frame's; empty: robot a).
  explicit Station(StationOptions options, std::vector<RobotId> team = {});
  /// Finishes if finish() was not called.
  ~Station();
  Station(const Station&) = delete;
  Station& operator=(const Station&) = delete;

  /// Puts an update on the ingest queue (any thread, any input); updates are processed in the
  /// order they are submitted. False, and nothing queued, once finish() has begun.
  bool submit(RobotUpdate update);
  /// Robot `robot` sends nothing more (it said BYE): with the time order, the others no longer
  /// wait for it.
  void endOfStream(RobotId robot);
  /// Records that an input left out `records` damaged records of a robot's stream (the end of
  /// the run says so with that robot's updates).
  void noteSkipped(RobotId robot, size_t records);
  /// Updates submitted and not yet processed.
  size_t queued() const;
  /// Closes the input, works off the queue, runs the last backend round and returns everything.
  /// Blocks until then; a second call returns an empty result.
  StationResult finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The file replay: a dataset's streams submitted to a Station in robot-time order, paced by
/// `options.speed`, then the result.
StationResult runStation(const DatasetStreams& input, const StationOptions& options = {});

/// The inter-robot loop closures as pose-graph edges (station ids).
std::vector<PoseGraphEdge> interRobotEdges(const std::vector<DetectedLoopClosure>& closures);

}  // namespace hydra_multi
