#pragma once
// The fused graph for others (docs/PROTOCOL.md "The fused graph"), in the ZeroMQ clone pattern.
// The station's GraphPublisher publishes its backend graph after every round on a PUB socket as
// the delta from the graph before (dsg/graph_delta.h), numbered by one global sequence; a ROUTER
// beside it answers a snapshot request with the whole latest graph and its sequence, so a
// subscriber that joins late or misses a delta (PUB drops them for late and slow subscribers)
// gets the whole state. GraphWatcher is such a subscriber; WatchState is its logic without
// sockets. Messages: frame 0 "HG", version 1, type, [sequence u64]; frame 1 a JSON summary; frame
// 2 a graph-delta or scene-graph record (dsg/io/binary_format.h).

#include <array>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/layer.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::net {

/// What a fused update says about itself (frame 1).
struct FusedSummary {
  uint64_t sequence = 0;  ///< 0: nothing published yet
  size_t round = 0;       ///< the backend round it is the result of
  size_t robots = 0, robots_aligned = 0;
  std::array<size_t, kAllLayers.size()> nodes{};  ///< per layer, indexed by Layer
  bool final = false;                             ///< the station's last: it is shutting down
};
/// "sequence 12 (round 11): agents 120, objects 40, ...; robots aligned 2 of 2".
std::string describeFused(const FusedSummary& summary);

struct GraphPublisherOptions {
  /// The snapshot service's endpoint (a ROUTER); the PUB binds the same host, port + 1 (or a free
  /// one with '*'), and the snapshot reply says which.
  std::string endpoint = "tcp://127.0.0.1:*";
  std::function<void(const std::string&)> log;
};

class GraphPublisher {
 public:
  static Result<std::unique_ptr<GraphPublisher>> create(GraphPublisherOptions options);
  /// Sends the final graph marked `final`, then stops its thread.
  ~GraphPublisher();
  const std::string& endpoint() const;         ///< the snapshot service
  const std::string& publishEndpoint() const;  ///< the PUB socket
  /// Queues a backend round's graph (any thread); its thread diffs it against the last one and
  /// publishes the delta with the next sequence.
  void publish(const SceneGraph& graph, size_t round, size_t robots, size_t robots_aligned);
  /// Publishes an end marker (the station is shutting down), and waits up to `timeout` for what
  /// is queued to go out.
  void close(std::chrono::milliseconds timeout = std::chrono::milliseconds(1000));
  uint64_t published() const;  ///< deltas published

 private:
  struct Impl;
  explicit GraphPublisher(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// A subscriber's state: the latest graph, by sequence.
class WatchState {
 public:
  enum class Outcome { kApplied, kStale, kGap, kBroken };
  /// A whole graph (a snapshot reply): taken when it is newer than what is held.
  Outcome onSnapshot(const FusedSummary& summary, SceneGraph graph);
  /// A delta: applied when it follows what is held; older ones are stale; a later one is a gap
  /// (ask for a snapshot); one that does not apply is broken (ask for a snapshot too).
  Outcome onDelta(const FusedSummary& summary, const GraphDelta& delta);
  uint64_t sequence() const { return summary_.sequence; }
  const FusedSummary& summary() const { return summary_; }
  const SceneGraph& graph() const { return graph_; }
  bool started() const { return started_; }

 private:
  FusedSummary summary_;
  SceneGraph graph_;
  bool started_ = false;
};

struct GraphWatcherOptions {
  std::string connect;  ///< the station's snapshot service (station --publish)
  double request_timeout_s = 5.0;
  std::function<void(const std::string&)> log;
};

class GraphWatcher {
 public:
  explicit GraphWatcher(GraphWatcherOptions options);
  ~GraphWatcher();
  /// Works for about `budget`: asks for a snapshot when it has none or saw a gap, takes deltas.
  /// `each` is called for every fused update taken (a snapshot or a delta). An error: the
  /// station does not answer, or answers what is not a fused graph.
  Status pump(std::chrono::milliseconds budget, const std::function<void(const WatchState&)>& each);
  const WatchState& state() const;
  bool ended() const;  ///< the station published its final graph
  size_t snapshots() const;
  size_t deltas() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::net
