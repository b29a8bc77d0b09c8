#include "hydra_multi/station/station.h"

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

namespace hydra_multi {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// What the backend works on: a copy of the frontend's state.
struct Snapshot {
  SceneGraph graph;
  std::map<RobotId, RobotFrontendState> robots;
  std::vector<PoseGraphEdge> inter_robot;
  std::vector<double> support;  ///< per inter-robot edge, for the alignment's consensus
  size_t after_update = 0;
  RobotId root;  ///< the robot whose frame should be global (preferredRoot)
};

Snapshot takeSnapshot(const SceneGraphProcessor& processor, const LoopClosureDetector& detector,
                      size_t after_update, RobotId root, const StationOptions& options) {
  Snapshot s;
  s.graph = processor.graph();
  for (const RobotId r : processor.robots()) s.robots[r] = *processor.robot(r);
  if (options.loop_closure_filter) {
    std::vector<DetectedLoopClosure> kept;
    for (const DetectedLoopClosure& c : detector.loopClosures()) {
      if (options.loop_closure_filter(c, s.graph)) kept.push_back(c);
    }
    s.inter_robot = interRobotEdges(kept);
    s.support = interRobotSupport(kept);
  } else {
    s.inter_robot = interRobotEdges(detector.loopClosures());
    s.support = interRobotSupport(detector.loopClosures());
  }
  s.after_update = after_update;
  s.root = root;
  return s;
}

// The global frame should be the first robot's of the team (robot a); a robot the station has
// nothing of cannot hold it, so it is the first robot with an update applied.
RobotId preferredRoot(const SceneGraphProcessor& processor, const DatasetStreams& input) {
  const std::vector<RobotId> with_data = processor.robotsWithData();
  if (!with_data.empty()) return with_data.front();
  return input.robots.empty() ? RobotId(0)
                              : *std::min_element(input.robots.begin(), input.robots.end());
}

}  // namespace

std::vector<PoseGraphEdge> interRobotEdges(const std::vector<DetectedLoopClosure>& closures) {
  std::vector<PoseGraphEdge> edges;
  for (const DetectedLoopClosure& c : closures) {
    if (!c.interRobot()) continue;
    PoseGraphEdge e;
    e.from = c.keyframe_a;
    e.to = c.keyframe_b;
    e.T_from_to = c.T_a_b;
    e.information = c.information;
    e.kind = PoseGraphEdge::Kind::kLoopClosure;
    edges.push_back(e);
  }
  return edges;
}

StationResult runStation(const DatasetStreams& input, const StationOptions& options) {
  const auto log = [&](const std::string& line) {
    if (options.log) options.log(line);
  };
  const Clock::time_point start = Clock::now();
  StationResult result;
  result.robots = input.robots.size();
  const RobotId team_first = input.robots.empty()
                                 ? RobotId(0)
                                 : *std::min_element(input.robots.begin(), input.robots.end());
  std::optional<RobotId> global;  // the robot whose frame the backend's graph is in
  SceneGraphProcessor processor(options.processor, options.log);
  LoopClosureDetector detector(options.detector);
  Backend backend(options.backend);

  // The hand-off between the two threads.
  std::mutex mutex;
  std::condition_variable wake;
  std::optional<Snapshot> pending;
  bool backend_busy = false, done = false;
  const auto runRound = [&](const Snapshot& s) {
    std::vector<BackendRobot> robots;
    for (const auto& [robot, state] : s.robots) {
      robots.push_back({robot, &state.pose_graph, &state.control_points, &state.control_point_edges,
                        &state.mesh});
    }
    RoundTiming timing;
    timing.round = result.rounds.size();
    timing.after_update = s.after_update;
    timing.report = backend.round(s.graph, robots, s.inter_robot, s.root, s.support);
    result.rounds.push_back(timing);
    // Say whose frame the map is in when it is not the team's first robot's, and when it moves.
    const RobotId now = backend.alignment().root().value_or(s.root);
    if (!global && now != team_first)
      log("station: the global frame is robot " + now.str() + "'s: the station has no update of " +
          team_first.str() + " yet");
    if (global && now != *global)
      log("station: the global frame moves to robot " + now.str() + "'s (aligned with robot " +
          global->str() + ")");
    global = now;
    log("backend round " + std::to_string(timing.round) + " after update " +
        std::to_string(s.after_update) + ": " + std::to_string(timing.report.robots_aligned) + "/" +
        std::to_string(timing.report.robots) + " robots aligned, " +
        std::to_string(timing.report.inter_robot_inliers) + "/" +
        std::to_string(timing.report.inter_robot_loop_closures) +
        " inter-robot loop closures kept, " + std::to_string(timing.report.merges_accepted) + "/" +
        std::to_string(timing.report.merges_proposed) + " merges, " +
        (timing.report.label_merges > 0
             ? std::to_string(timing.report.label_merges) + " by label votes, "
             : std::string()) +
        std::to_string(timing.report.nodes) + " nodes, " + std::to_string(timing.report.rooms) +
        " rooms, " + std::to_string(timing.report.time_s) + " s");
  };
  std::thread backend_thread([&] {
    for (;;) {
      Snapshot s;
      {
        std::unique_lock<std::mutex> lock(mutex);
        wake.wait(lock, [&] { return pending.has_value() || done; });
        if (!pending) return;
        s = std::move(*pending);
        pending.reset();
        backend_busy = true;
      }
      runRound(s);
      std::lock_guard<std::mutex> lock(mutex);
      backend_busy = false;
    }
  });

  const int64_t first_time = input.updates.empty() ? 0 : input.updates.front().time_ns;
  size_t news = 0;  // loop closures or updates since the last hand-off
  for (size_t i = 0; i < input.updates.size(); ++i) {
    const RobotUpdate& update = input.updates[i];
    if (options.speed > 0.0) {
      const auto due = start + std::chrono::nanoseconds(static_cast<int64_t>(
                                   double(update.time_ns - first_time) / options.speed));
      std::this_thread::sleep_until(due);
    }
    const Clock::time_point t0 = Clock::now();
    const UpdateReport report = processor.process(update);
    UpdateTiming timing;
    timing.robot = update.robot;
    timing.sequence = update.sequence;
    timing.time_ns = update.time_ns;
    if (report.outcome == UpdateOutcome::kApplied) {
      timing.loop_closures = detector.update(processor, report.new_keyframes).size();
      ++news;
    }
    timing.frontend_ms = millisecondsSince(t0);
    // Hand the backend the latest state when it is idle and there is something new.
    bool idle = false;
    {
      std::lock_guard<std::mutex> lock(mutex);
      idle = !backend_busy && !pending;
    }
    if (idle && news > 0) {
      const Clock::time_point t1 = Clock::now();
      Snapshot s =
          takeSnapshot(processor, detector, i + 1, preferredRoot(processor, input), options);
      {
        std::lock_guard<std::mutex> lock(mutex);
        pending = std::move(s);
      }
      wake.notify_one();
      news = 0;
      timing.handoff_ms = millisecondsSince(t1);
    }
    result.updates.push_back(timing);
    if ((i + 1) % 100 == 0)
      log("frontend: " + std::to_string(i + 1) + "/" + std::to_string(input.updates.size()) +
          " updates, " + std::to_string(detector.loopClosures().size()) + " loop closures");
  }
  detector.flush(processor);
  // A robot whose stream did not all arrive (damaged records, a gap, rejected updates, nothing at
  // all): what the station has of it and where its map stops.
  for (const RobotId robot : input.robots) {
    const auto damaged = input.skipped_per_robot.find(robot);
    const size_t skipped = damaged == input.skipped_per_robot.end() ? 0 : damaged->second;
    if (!streamIsWhole(processor.order(robot), skipped))
      log(describeStream(robot, processor.order(robot), skipped));
  }
  // The last round runs on the final state, after whatever round is running now.
  {
    std::unique_lock<std::mutex> lock(mutex);
    pending = takeSnapshot(processor, detector, input.updates.size(),
                           preferredRoot(processor, input), options);
  }
  wake.notify_one();
  {
    std::unique_lock<std::mutex> lock(mutex);
    done = true;
  }
  wake.notify_one();
  backend_thread.join();

  result.graph = backend.graph();
  result.loop_closures = detector.loopClosures();
  result.inter_robot_inliers = backend.loopClosureInliers();
  result.alignment_inliers = backend.alignment().edgeInliers();
  result.merges = backend.merges();
  result.aligned = backend.aligned();
  result.counts = processor.counts();
  result.global_robot = global.value_or(team_first);
  for (const NodeId id : processor.graph().nodesInLayer(Layer::kAgents)) {
    if (const auto* agent = processor.graph().getNode(id).find<AgentAttributes>())
      result.keyframe_stamps[id] = agent->timestamp_ns;
  }
  result.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace hydra_multi
