#pragma once
// Hydra robots as station inputs (../shared/reference/spark-dsg-wire.md §2-3): for each robot the
// station was told of (`--spark-robot NAME=tcp://HOST:PORT`), a SUB that connects to its ZmqSink
// and takes the whole graphs it publishes in Spark-DSG's wire form. Each robot has its own thread,
// so a robot that is slow, silent or sends garbage never holds up the others. A graph is decoded
// (dsg/io/spark_binary.h), turned into a robot update (station/hydra_graph_input.h), stored by
// `persist` (the station's journal) and submitted to the Station. Graphs that queued up while one
// was taken are overtaken by the newest (each is whole, so nothing is lost; they are counted); a
// graph that does not decode or cannot be used is logged with the robot, the graph's number and
// the error, and the next is taken against the last good one. Hydra robots say no BYE: one that
// has sent a graph and then nothing for `done_after_s` counts as done. ZeroMQ stays inside.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/net/station_server.h"
#include "hydra_multi/station/hydra_graph_input.h"
#include "hydra_multi/station/station.h"

namespace hydra_multi::net {

struct HydraRobotSource {
  RobotId robot;
  std::string endpoint;  ///< the robot's ZmqSink, tcp://HOST:PORT
};

/// Parses NAME=tcp://HOST:PORT (NAME a robot letter); an error says what is wrong.
Result<HydraRobotSource> parseHydraRobotSource(const std::string& text);

struct HydraRobotsOptions {
  std::vector<HydraRobotSource> robots;
  HydraInputOptions input;
  io::spark::Version version = io::spark::kVersion;  ///< the robots' Spark-DSG
  size_t max_message_bytes = 64u << 20;              ///< a larger message drops the link
  /// Sent a graph, then nothing for this long: done (0: never; the station runs until stopped).
  double done_after_s = 0.0;
  /// Every this many seconds, one progress line per robot (0: none).
  double status_s = 10.0;
  std::function<void(const std::string&)> log;
  /// Stores an update before it is submitted (its robot, sequence, its record and the bytes of
  /// the graph it came from); an error leaves the update out and the graph is taken again whole.
  std::function<Status(const RobotUpdate& update, const std::string& record, size_t wire_bytes)>
      persist;
};

/// What became of one Hydra robot's graphs.
struct HydraRobotCounts {
  size_t graphs = 0;     ///< messages received
  size_t bytes = 0;      ///< of every message
  size_t overtaken = 0;  ///< received while another was taken, and skipped for a newer one
  size_t refused = 0;    ///< did not decode or could not be used
  size_t unchanged = 0;  ///< the same graph as the last one taken
  size_t updates = 0;    ///< submitted to the station
  size_t snapshots = 0;  ///< of the updates, whole ones
  uint64_t next_sequence = 0;
  size_t last_bytes = 0;  ///< of the last graph taken
};

class HydraRobots {
 public:
  /// Connects a SUB per robot; nothing is received before start(). An error names the robot.
  static Result<std::unique_ptr<HydraRobots>> create(Station& station, HydraRobotsOptions options);
  /// Stops the threads.
  ~HydraRobots();

  /// The station holds `robot`'s updates before `next_sequence` (replayed from its journal):
  /// its next graph goes whole, with that number. Before start() only.
  void resumeAt(RobotId robot, uint64_t next_sequence);
  void start();
  /// Stops taking graphs (a graph being taken is finished and submitted first).
  void stop();

  bool has(RobotId robot) const;
  /// Each robot's link: connected means a graph came within the last 3 s; done as above.
  std::map<RobotId, RobotLinkState> links() const;
  /// Robots that are done (they sent a graph, then nothing for done_after_s).
  size_t done() const;
  std::map<RobotId, HydraRobotCounts> counts() const;

 private:
  struct Impl;
  explicit HydraRobots(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::net
