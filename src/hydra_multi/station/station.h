#pragma once
// The station runtime (DESIGN.md "Data flow"): the frontend in the calling thread, the backend in
// its own. Updates arrive in robot-time order, paced by `speed` (1: real time, 10: ten times
// faster, 0: as fast as the frontend goes); each goes through the scene-graph processor and the
// loop-closure detector, timed. Whenever the backend is idle and the frontend has news, the
// frontend hands it a snapshot of its state (graph, per-robot pose graphs, control points,
// meshes, inter-robot loop closures) and goes on; the backend runs a round on it (backend.h). The
// frontend never waits for the backend. After the last update, the detector describes the
// remaining keyframes and the backend runs one last round on the final state.
// The global frame should be robot a's; each round asks for the first robot with an update applied
// (backend/initial_alignment.h moves the frame to it once it is aligned), so a robot the station
// has nothing of never takes the others with it.

#include <functional>
#include <string>
#include <vector>

#include "hydra_multi/backend/backend.h"
#include "hydra_multi/frontend/loop_closure_detector.h"
#include "hydra_multi/station/dataset_replay.h"

namespace hydra_multi {

struct StationOptions {
  double speed = 0.0;  ///< replay speed: 1 real time, 10 ten times faster, 0 as fast as possible
  ProcessorOptions processor;
  LoopClosureOptions detector;
  BackendOptions backend;
  std::function<void(const std::string&)> log;  ///< progress and warnings
  /// Evaluation only (the oracle-lc yardstick): the inter-robot loop closures the backend may
  /// see; the frontend's graph gives the keyframes' stamps. Empty: all of them.
  std::function<bool(const DetectedLoopClosure&, const SceneGraph&)> loop_closure_filter;
};

struct UpdateTiming {
  RobotId robot;
  uint64_t sequence = 0;
  int64_t time_ns = 0;
  double frontend_ms = 0.0;  ///< processing and detection
  double handoff_ms = 0.0;   ///< copying the state for the backend (0 when none)
  size_t loop_closures = 0;  ///< found by this update
};

struct RoundTiming {
  size_t round = 0;
  size_t after_update = 0;  ///< updates processed when the round's snapshot was taken
  BackendRoundReport report;
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
  std::map<RobotId, RobotFrameAlignment> aligned;
  UpdateCounts counts;
  /// The robot whose frame `graph` is in: robot a's, unless the station had nothing of it when
  /// the map began (then the first robot it had data of, until a is aligned with it).
  RobotId global_robot;
  size_t robots = 0;
  double wall_s = 0.0;
};

/// Runs the station over a dataset's streams.
StationResult runStation(const DatasetStreams& input, const StationOptions& options = {});

/// The inter-robot loop closures as pose-graph edges (station ids).
std::vector<PoseGraphEdge> interRobotEdges(const std::vector<DetectedLoopClosure>& closures);

}  // namespace hydra_multi
