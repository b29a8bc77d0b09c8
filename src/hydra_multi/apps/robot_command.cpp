// `hydra-multi robot --dataset DIR --robot R --connect ENDPOINT [--speed X]`: robot R of a recorded
// dataset played as a live robot (net/robot_client.h): its updates sent to a station as its robot
// time comes (`--speed 0`: as fast as the station acknowledges), kept until acknowledged and sent
// again after a reconnect; BYE once the station holds them all. `--mission-start T` puts the first
// update at Unix time T: a robot process restarted mid-mission takes the updates due before it
// started as its map (it made them while down) and sends them as a snapshot when the station
// asks. `--full-resend` sends the whole map every update (the paper's robots). `--spark --bind
// ENDPOINT` speaks as a Hydra robot instead: a PUB that binds and publishes the robot's whole
// graph (robot-side ids, as Hydra's, with its mesh) in Spark-DSG's wire form after every update, as
// its robot time comes; no station protocol, no acknowledgements. Its agents carry their bags of
// words (dbow_ids, dbow_values) as Hydra's do; keypoints, the pose graph's edges and the
// deformation graph are not sent, as Hydra sends none. `--graph FILE` publishes one graph file
// every `--every` s instead; `--move X,Y,Z,YAW_DEG` publishes the graph as a robot whose odometric
// frame lies elsewhere would have mapped it.

#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>
#include <thread>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/stop_signals.h"
#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/dataset_files.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/io/spark_graph.h"
#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/net/keys.h"
#include "hydra_multi/net/robot_client.h"
#include "hydra_multi/net/spark_publisher.h"
#include "hydra_multi/station/hydra_graph_input.h"

namespace hydra_multi::apps {

Result<std::array<double, 4>> parseMove(const std::string& text) {
  std::array<double, 4> values{};
  std::stringstream in(text);
  std::string item;
  size_t n = 0;
  while (std::getline(in, item, ',')) {
    if (n == 4) return Error{"'" + text + "' has more than X,Y,Z,YAW_DEG"};
    size_t used = 0;
    try {
      values[n] = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(values[n]))
      return Error{"'" + item + "' in '" + text + "' is not a finite number (X,Y,Z,YAW_DEG)"};
    ++n;
  }
  if (n != 4) return Error{"'" + text + "' is not X,Y,Z,YAW_DEG (four numbers)"};
  return values;
}

namespace {

void move(io::spark::Graph& graph, const std::optional<std::array<double, 4>>& by) {
  if (!by) return;
  io::moveSparkGraph(graph, {(*by)[0], (*by)[1], (*by)[2]}, (*by)[3] * M_PI / 180.0);
}

// A Hydra robot whose map no longer changes: one graph file, published every `every_s`.
int publishGraphFile(const RobotCommandOptions& o) {
  io::spark::Graph graph;
  if (io::formatFromPath(o.graph) == io::FileFormat::kSparkBinary) {
    auto bytes = io::readFile(o.graph);
    if (!bytes) return fail(bytes.error());
    auto decoded = io::spark::decodeFile(bytes.value());
    if (!decoded) return fail(o.graph + ": " + decoded.error());
    graph = std::move(decoded).value();
  } else {
    auto loaded = io::loadSceneGraph(o.graph);
    if (!loaded) return fail(loaded.error());
    graph = io::sparkFromSceneGraph(loaded.value(), true);
  }
  move(graph, o.move);
  auto publisher =
      net::SparkPublisher::create(o.bind, true, *io::spark::Version::parse(o.spark_version));
  if (!publisher) return fail(publisher.error());
  if (!o.quiet)
    std::cerr << "robot: publishing " << o.graph << " in Spark-DSG's wire form on "
              << publisher.value()->endpoint() << " every " << o.every_s << " s" << std::endl;
  const StopSignals signals;
  // A SUB that has just connected misses what was sent before (ZeroMQ's slow joiner).
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const auto period = std::chrono::duration<double>(o.every_s);
  auto due = std::chrono::steady_clock::now();
  for (size_t sent = 0; (o.count == 0 || sent < o.count) && !StopSignals::requested(); ++sent) {
    publisher.value()->publish(graph);
    due += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    while (std::chrono::steady_clock::now() < due && !StopSignals::requested())
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  std::cerr << "robot: published " << o.graph << " " << publisher.value()->published() << " times ("
            << publisher.value()->lastBytes() << " bytes each)" << std::endl;
  return 0;
}

// A Hydra-speaking robot: the graph its updates have built, published after each as it is due.
int publishAsHydra(const RobotCommandOptions& o, const std::vector<RobotUpdate>& updates) {
  using Clock = std::chrono::steady_clock;
  auto publisher =
      net::SparkPublisher::create(o.bind, true, *io::spark::Version::parse(o.spark_version));
  if (!publisher) return fail(publisher.error());
  if (!o.quiet)
    std::cerr << "robot " << o.robot << ": publishing its graph in Spark-DSG's wire form on "
              << publisher.value()->endpoint() << std::endl;
  // A SUB that has just connected misses what was sent before (ZeroMQ's slow joiner).
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const StopSignals signals;
  RobotStreamState state;
  const Clock::time_point start = Clock::now();
  const int64_t first_time = updates.front().time_ns;
  for (const RobotUpdate& u : updates) {
    const Clock::time_point due =
        start +
        std::chrono::nanoseconds(static_cast<int64_t>(double(u.time_ns - first_time) / o.speed));
    while (Clock::now() < due && !StopSignals::requested())
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (StopSignals::requested()) break;
    if (Status s = state.add(u); !s) return fail("robot " + o.robot + ": " + s.message());
    auto graph = hydraGraphOfMap(state.snapshot());
    if (!graph)
      return fail("robot " + o.robot + ": update " + std::to_string(u.sequence) + ": " +
                  graph.error());
    move(graph.value(), o.move);
    publisher.value()->publish(std::move(graph).value());
  }
  // The last graph goes out before the PUB closes (it lingers 1 s).
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  std::cerr << "robot " << o.robot << ": published " << publisher.value()->published()
            << " graphs of " << updates.size() << " updates (the last "
            << publisher.value()->lastBytes() << " bytes)" << std::endl;
  return 0;
}

}  // namespace

int runRobotCommand(const RobotCommandOptions& o) {
  using Clock = std::chrono::steady_clock;
  if (!o.graph.empty()) return publishGraphFile(o);
  auto manifest = io::readDatasetManifest(o.dataset);
  if (!manifest) return fail(manifest.error());
  const io::DatasetRobot* entry = nullptr;
  std::string known;
  for (const io::DatasetRobot& r : manifest.value().robots) {
    if (r.robot.str() == o.robot) entry = &r;
    known += (known.empty() ? "" : ", ") + r.robot.str();
  }
  if (entry == nullptr)
    return fail("no robot '" + o.robot + "' in " + o.dataset + " (robots: " + known + ")");
  auto records = io::loadRobotStream(entry->stream, entry->robot);
  if (!records) return fail(records.error());
  for (const std::string& skipped : records.value().skipped)
    std::cerr << "robot " << o.robot << ": skipped " << skipped << std::endl;
  const std::vector<RobotUpdate>& updates = records.value().updates;
  if (updates.empty()) return fail(entry->stream + ": no intact update to send");
  if (o.spark) return publishAsHydra(o, updates);

  net::RobotClientOptions options;
  options.connect = o.connect;
  options.full_resend = o.full_resend;
  options.compress = o.compress == "zstd";
  if (!o.key.empty()) {
    auto secret = net::readKey(o.key);
    if (!secret) return fail(secret.error());
    auto station_key = net::readKey(o.station_key);
    if (!station_key) return fail(station_key.error());
    options.secret_key = secret.value();
    options.station_key = station_key.value();
  }
  if (!o.quiet) options.log = [](const std::string& line) { std::cerr << line << std::endl; };
  net::RobotClient client(entry->robot, updates.front().provided_layers, options);
  const Clock::time_point now = Clock::now();
  // The mission's start on this process's clock.
  Clock::time_point start = now;
  if (o.mission_start_s) {
    const double unix_now =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    start = now + std::chrono::duration_cast<Clock::duration>(
                      std::chrono::duration<double>(*o.mission_start_s - unix_now));
  }
  const int64_t first_time = updates.front().time_ns;
  // The timeout counts from when the last update is due (with --speed 0: from now), so that a
  // mission in real time is not cut short by it.
  Clock::time_point last_due = now;
  if (o.speed > 0.0)
    last_due = std::max(now, start + std::chrono::nanoseconds(static_cast<int64_t>(
                                         double(updates.back().time_ns - first_time) / o.speed)));
  const Clock::time_point deadline = last_due + std::chrono::duration_cast<Clock::duration>(
                                                    std::chrono::duration<double>(o.timeout_s));
  size_t folded = 0;
  for (const RobotUpdate& u : updates) {
    if (o.speed > 0.0) {
      const auto due = start + std::chrono::nanoseconds(
                                   static_cast<int64_t>(double(u.time_ns - first_time) / o.speed));
      if (due < now) {  // made while this process was down: the map has it
        client.fold(u);
        ++folded;
        continue;
      }
    }
    if (o.speed > 0.0) {
      const auto due = start + std::chrono::nanoseconds(
                                   static_cast<int64_t>(double(u.time_ns - first_time) / o.speed));
      while (Clock::now() < due && client.fatal().empty())
        client.pump(std::chrono::milliseconds(10));
    }
    while (!client.enqueue(u) && client.fatal().empty() && Clock::now() < deadline)
      client.pump(std::chrono::milliseconds(10));
    client.pump(std::chrono::milliseconds(0));
    if (!client.fatal().empty()) return fail(o.connect + ": " + client.fatal());
    if (Clock::now() >= deadline) break;
  }
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  const bool finished = client.finish(std::max(left, std::chrono::milliseconds(0)));
  const net::RobotClientCounts& c = client.counts();
  std::cout << "robot " << o.robot << " to " << o.connect << ": " << updates.size() << " updates, "
            << (folded ? std::to_string(folded) + " made before this process started, " : "")
            << c.sent << " sent, " << c.resent << " sent again, " << c.snapshots
            << " snapshots asked for, " << c.acknowledged << " acknowledged, " << c.refused
            << " refused, " << c.connections
            << (c.connections == 1 ? " connection, " : " connections, ") << c.bytes << " bytes"
            << (c.bye_unanswered ? ", BYE not answered" : "")
            << (c.lost_acknowledged
                    ? ", " + std::to_string(c.lost_acknowledged) + " acknowledged and then lost"
                    : std::string())
            << "\n";
  if (!client.fatal().empty()) return fail(o.connect + ": " + client.fatal());
  if (!finished) {
    std::ostringstream seconds;
    seconds << o.timeout_s;
    return fail(o.connect + ": the station did not take every update within " + seconds.str() +
                " s" + (o.speed > 0.0 ? " of the last one's time" : "") + " (" +
                std::to_string(client.unacknowledged()) + " unacknowledged)");
  }
  return 0;
}

}  // namespace hydra_multi::apps
