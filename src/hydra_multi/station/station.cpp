#include "hydra_multi/station/station.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <iterator>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "hydra_multi/station/freed_memory.h"
#include "hydra_multi/station/frontend_digest.h"
#include "hydra_multi/station/time_order.h"

namespace hydra_multi {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// What the backend works on: the frontend's state, as the changes applied since the last hand-off
// (the backend thread keeps its own copy of the graph and the robots' states up to date with
// them: no copy of the whole state stops the frontend).
struct Snapshot {
  std::vector<AppliedDelta> deltas;
  std::vector<RobotId> robots;  ///< every robot the frontend has heard of
  std::vector<PoseGraphEdge> inter_robot;
  std::vector<double> support;  ///< per inter-robot edge, for the alignment's consensus
  size_t after_update = 0;
  RobotId root;  ///< the robot whose frame should be global (preferredRoot)
  std::map<RobotId, RobotProgress> progress;
  bool last = false;  ///< the final state: its round starts from scratch
};

Snapshot takeSnapshot(SceneGraphProcessor& processor, const LoopClosureDetector& detector,
                      size_t after_update, RobotId root, const StationOptions& options) {
  Snapshot s;
  s.deltas = processor.takeDeltas();
  for (const RobotId r : processor.robots()) {
    s.robots.push_back(r);
    RobotProgress& p = s.progress[r];
    p.robot_time_ns = processor.robot(r)->last_time_ns;
    if (const UpdateSequencer* order = processor.order(r)) {
      p.applied = order->counts().appliedTotal();
      p.next_sequence = order->nextSequence();
    }
  }
  if (options.loop_closure_filter) {
    std::vector<DetectedLoopClosure> kept;
    for (const DetectedLoopClosure& c : detector.loopClosures()) {
      if (options.loop_closure_filter(c, processor.graph())) kept.push_back(c);
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
RobotId preferredRoot(const SceneGraphProcessor& processor, RobotId team_first) {
  const std::vector<RobotId> with_data = processor.robotsWithData();
  return with_data.empty() ? team_first : with_data.front();
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

struct Station::Impl {
  Impl(StationOptions station_options, std::vector<RobotId> expected)
      : options(std::move(station_options)),
        team(std::move(expected)),
        team_first(team.empty() ? RobotId(0) : *std::min_element(team.begin(), team.end())),
        processor(options.processor, [this](const std::string& line) { log(line); }),
        detector(options.detector),
        backend(options.backend) {
    processor.keepDeltas();
    if (options.keep_freed_mb > 0) keepFreedMemory();
    if (options.time_order_hold_s > 0.0)
      time_order.emplace(std::chrono::duration_cast<Clock::duration>(
                             std::chrono::duration<double>(options.time_order_hold_s)),
                         options.expected_robots);
    std::ostringstream hold;
    hold << options.time_order_hold_s;
    hold_text = hold.str();
  }
  // Moves what the time order releases onto the queue (under queue_mutex); says a robot's first
  // late update (time_order.h).
  void releaseOrdered(bool everything = false) {
    if (!time_order) return;
    const Clock::time_point now = Clock::now();
    for (RobotUpdate& u : time_order->release(now, everything)) {
      const auto late = time_order->late().find(u.robot);
      if (late != time_order->late().end() && late->second > 0 && said_late.insert(u.robot).second)
        log("station: robot " + u.robot.str() + "'s update " + std::to_string(u.sequence) +
            " came after updates of later robot time had gone on without it (the order's hold, " +
            hold_text +
            " s, ran out): from here the map may differ from run's; a longer --order-hold waits "
            "longer for a silent robot");
      queue.emplace_back(std::move(u), now);
    }
  }

  void log(const std::string& line) {
    if (!options.log) return;
    std::lock_guard<std::mutex> lock(log_mutex);
    options.log(line);
  }

  void runRound(const Snapshot& s);
  void backendLoop();
  void frontendLoop();
  void process(const RobotUpdate& update, Clock::time_point submitted);
  void handOff(size_t after_update, bool last = false);
  void endOfInput();
  size_t queued() const;

  StationOptions options;
  std::vector<RobotId> team;
  RobotId team_first;
  const Clock::time_point start = Clock::now();
  std::mutex log_mutex;

  // The ingest queue, between the inputs and the frontend thread.
  mutable std::mutex queue_mutex;
  std::condition_variable queue_wake;
  std::deque<std::pair<RobotUpdate, Clock::time_point>> queue;
  std::optional<TimeOrder> time_order;  // with options.time_order_hold_s: before the queue
  std::set<RobotId> said_late;          // robots whose late updates the log has said
  std::string hold_text;
  bool input_closed = false;
  std::map<RobotId, size_t> skipped;  // damaged records per robot, as inputs report them

  // The frontend thread's state.
  SceneGraphProcessor processor;
  LoopClosureDetector detector;
  size_t processed = 0;
  size_t news = 0;  // updates applied since the last hand-off

  // The hand-off between the frontend and the backend thread.
  Backend backend;
  std::mutex handoff_mutex;
  std::condition_variable handoff_wake;
  std::optional<Snapshot> pending;
  bool backend_busy = false, backend_done = false;
  // The backend thread's copy of the frontend's graph and robots' states (Snapshot).
  SceneGraph frontend_graph;
  std::map<RobotId, RobotFrontendState> frontend_robots;
  std::optional<RobotId> global;  // the robot whose frame the backend's graph is in

  StationResult result;
  std::thread frontend_thread, backend_thread;
  bool finished = false;
};

void Station::Impl::runRound(const Snapshot& s) {
  std::vector<BackendRobot> robots;
  for (const auto& [robot, state] : frontend_robots) {
    robots.push_back(
        {robot, &state.pose_graph, &state.control_points, &state.control_point_edges, &state.mesh});
  }
  RoundTiming timing;
  timing.round = result.rounds.size();
  timing.after_update = s.after_update;
  timing.report = backend.round(frontend_graph, robots, s.inter_robot, s.root, s.support, s.last);
  if (options.keep_freed_mb > 0 && s.last) {
    handBackFreedMemory();  // no round follows
  } else if (options.keep_freed_mb > 0) {
    timing.freed = trimFreedMemory(options.keep_freed_mb << 20);
  }
  result.rounds.push_back(timing);
  if (options.on_round) {
    options.on_round({backend.graph(), timing, backend.loopClosures(), backend.merges(),
                      backend.aligned(), s.progress});
  }
  // Say whose frame the map is in when it is not the team's first robot's, and when it moves.
  const RobotId now = backend.alignment().root().value_or(s.root);
  if (!global && now != team_first)
    log("station: the global frame is robot " + now.str() + "'s: the station has no update of " +
        team_first.str() + " yet");
  if (global && now != *global)
    log("station: the global frame moves to robot " + now.str() + "'s (aligned with robot " +
        global->str() + ")");
  global = now;
  const BackendRoundReport& r = timing.report;
  log("backend round " + std::to_string(timing.round) + " after update " +
      std::to_string(s.after_update) + ": " + std::to_string(r.robots_aligned) + "/" +
      std::to_string(r.robots) + " robots aligned" +
      (r.robots_afresh > 0 ? " (" + std::to_string(r.robots_afresh) + " new or re-aligned)"
                           : std::string()) +
      ", " + std::to_string(r.inter_robot_inliers) + "/" +
      std::to_string(r.inter_robot_loop_closures) + " inter-robot loop closures kept, " +
      std::to_string(r.merges_accepted) + "/" + std::to_string(r.merges_proposed) + " merges, " +
      (r.label_merges > 0 ? std::to_string(r.label_merges) + " by label votes, " : std::string()) +
      std::to_string(r.nodes) + " nodes, " + std::to_string(r.rooms) + " rooms, " +
      std::to_string(r.time_s) + " s");
}

void Station::Impl::backendLoop() {
  for (;;) {
    Snapshot s;
    {
      std::unique_lock<std::mutex> lock(handoff_mutex);
      handoff_wake.wait(lock, [&] { return pending.has_value() || backend_done; });
      if (!pending) return;
      s = std::move(*pending);
      pending.reset();
      backend_busy = true;
    }
    for (const RobotId robot : s.robots) {
      if (!frontend_robots.count(robot)) frontend_robots[robot].frame = robot;
    }
    for (const AppliedDelta& delta : s.deltas) {
      // The frontend applied each to the same graph; failing here would be a station fault.
      if (Status status = applyDelta(frontend_graph, delta.graph); !status)
        log("station: error: the backend's copy of the graph did not take a delta the frontend "
            "applied (" +
            status.message() + "); the round goes on without it");
      applyStateDelta(frontend_robots[delta.robot.robot], delta.robot);
    }
    runRound(s);
    std::lock_guard<std::mutex> lock(handoff_mutex);
    backend_busy = false;
  }
}

void Station::Impl::handOff(size_t after_update, bool last) {
  Snapshot s = takeSnapshot(processor, detector, after_update, preferredRoot(processor, team_first),
                            options);
  s.last = last;
  {
    std::lock_guard<std::mutex> lock(handoff_mutex);
    if (pending) {  // not taken yet: its deltas go first
      s.deltas.insert(s.deltas.begin(), std::make_move_iterator(pending->deltas.begin()),
                      std::make_move_iterator(pending->deltas.end()));
    }
    pending = std::move(s);
  }
  handoff_wake.notify_one();
}

void Station::Impl::process(const RobotUpdate& update, Clock::time_point submitted) {
  const Clock::time_point t0 = Clock::now();
  const UpdateReport report = processor.process(update);
  UpdateTiming timing;
  timing.robot = update.robot;
  timing.sequence = update.sequence;
  timing.time_ns = update.time_ns;
  timing.queue_ms = std::chrono::duration<double, std::milli>(t0 - submitted).count();
  if (report.outcome == UpdateOutcome::kApplied) {
    timing.loop_closures = detector.update(processor, report.new_keyframes).size();
    ++news;
  }
  timing.frontend_ms = millisecondsSince(t0);
  ++processed;
  // Hand the backend the latest state when it is idle and there is something new.
  bool idle = false;
  {
    std::lock_guard<std::mutex> lock(handoff_mutex);
    idle = !backend_busy && !pending;
  }
  if (idle && news > 0) {
    const Clock::time_point t1 = Clock::now();
    handOff(processed);
    news = 0;
    timing.handoff_ms = millisecondsSince(t1);
  }
  result.updates.push_back(timing);
  if (processed % 100 == 0)
    log("frontend: " + std::to_string(processed) + " updates, " + std::to_string(queued()) +
        " queued, " + std::to_string(detector.loopClosures().size()) + " loop closures");
}

size_t Station::Impl::queued() const {
  std::lock_guard<std::mutex> lock(queue_mutex);
  return queue.size() + (time_order ? time_order->held() : 0);
}

void Station::Impl::frontendLoop() {
  for (;;) {
    std::pair<RobotUpdate, Clock::time_point> next;
    {
      std::unique_lock<std::mutex> lock(queue_mutex);
      for (;;) {
        releaseOrdered(input_closed);
        if (!queue.empty() || input_closed) break;
        const auto deadline = time_order ? time_order->deadline() : std::nullopt;
        if (deadline)
          queue_wake.wait_until(lock, *deadline);
        else
          queue_wake.wait(lock);
      }
      if (queue.empty()) break;  // closed and worked off
      next = std::move(queue.front());
      queue.pop_front();
    }
    process(next.first, next.second);
  }
  endOfInput();
}

void Station::Impl::endOfInput() {
  detector.flush(processor);
  // A robot whose stream did not all arrive (damaged records, a gap, rejected updates, nothing at
  // all): what the station has of it and where its map stops.
  std::set<RobotId> robots(team.begin(), team.end());
  for (const RobotId robot : processor.robots()) robots.insert(robot);
  std::map<RobotId, size_t> damaged;
  {
    std::lock_guard<std::mutex> lock(queue_mutex);
    damaged = skipped;
  }
  for (const RobotId robot : robots) {
    const size_t records = damaged.count(robot) ? damaged.at(robot) : 0;
    if (!streamIsWhole(processor.order(robot), records))
      log(describeStream(robot, processor.order(robot), records));
  }
  result.robots = robots.size();
  // The last round runs on the final state, after whatever round is running now (none when no
  // update ever came), from scratch: the final map does not depend on when rounds ran.
  if (processed > 0) handOff(processed, true);
  {
    std::lock_guard<std::mutex> lock(handoff_mutex);
    backend_done = true;
  }
  handoff_wake.notify_one();
}

Station::Station(StationOptions options, std::vector<RobotId> team)
    : impl_(std::make_unique<Impl>(std::move(options), std::move(team))) {
  impl_->backend_thread = std::thread([this] { impl_->backendLoop(); });
  impl_->frontend_thread = std::thread([this] { impl_->frontendLoop(); });
}

Station::~Station() {
  if (!impl_->finished) finish();
}

bool Station::submit(RobotUpdate update) {
  {
    std::lock_guard<std::mutex> lock(impl_->queue_mutex);
    if (impl_->input_closed) return false;
    if (impl_->time_order) {
      impl_->time_order->add(std::move(update));
      impl_->releaseOrdered();
    } else {
      impl_->queue.emplace_back(std::move(update), Clock::now());
    }
  }
  impl_->queue_wake.notify_one();
  return true;
}

void Station::endOfStream(RobotId robot) {
  {
    std::lock_guard<std::mutex> lock(impl_->queue_mutex);
    if (!impl_->time_order) return;
    impl_->time_order->finish(robot);
    impl_->releaseOrdered();
  }
  impl_->queue_wake.notify_one();
}

void Station::noteSkipped(RobotId robot, size_t records) {
  std::lock_guard<std::mutex> lock(impl_->queue_mutex);
  impl_->skipped[robot] += records;
}

size_t Station::queued() const { return impl_->queued(); }

StationResult Station::finish() {
  Impl& s = *impl_;
  if (s.finished) return {};
  {
    std::lock_guard<std::mutex> lock(s.queue_mutex);
    s.input_closed = true;
  }
  s.queue_wake.notify_one();
  s.frontend_thread.join();
  s.backend_thread.join();
  s.finished = true;

  StationResult& result = s.result;
  result.graph = s.backend.graph();
  result.loop_closures = s.detector.loopClosures();
  result.inter_robot_inliers = s.backend.loopClosureInliers();
  result.alignment_inliers = s.backend.alignment().edgeInliers();
  result.merges = s.backend.merges();
  result.aligned = s.backend.aligned();
  result.counts = s.processor.counts();
  if (s.time_order) result.late = s.time_order->late();
  result.global_robot = s.global.value_or(s.team_first);
  for (const NodeId id : s.processor.graph().nodesInLayer(Layer::kAgents)) {
    if (const auto* agent = s.processor.graph().getNode(id).find<AgentAttributes>())
      result.keyframe_stamps[id] = agent->timestamp_ns;
  }
  result.frontend_digest = frontendDigest(s.processor);
  result.wall_s = std::chrono::duration<double>(Clock::now() - s.start).count();
  return std::move(result);
}

StationResult runStation(const DatasetStreams& input, const StationOptions& options) {
  Station station(options, input.robots);
  for (const auto& [robot, records] : input.skipped_per_robot)
    if (records > 0) station.noteSkipped(robot, records);
  // Robot time, paced by `speed`: each update is due when its time has passed at that speed.
  const Clock::time_point start = Clock::now();
  const int64_t first_time = input.updates.empty() ? 0 : input.updates.front().time_ns;
  for (const RobotUpdate& update : input.updates) {
    if (options.speed > 0.0) {
      std::this_thread::sleep_until(
          start + std::chrono::nanoseconds(
                      static_cast<int64_t>(double(update.time_ns - first_time) / options.speed)));
    }
    station.submit(update);
  }
  return station.finish();
}

}  // namespace hydra_multi
