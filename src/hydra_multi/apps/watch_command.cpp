// `hydra-multi watch --connect ENDPOINT [--out FILE] [--count N] [--timeout S]`: a subscriber of
// a station's fused graph (station --publish; net/fused_graph.h). It asks for a snapshot, then
// takes the deltas; a gap asks for a snapshot again. One line per fused update on stdout
// (sequence, round, nodes per layer, robots aligned); with --out, the latest graph written after
// every update. Ends at the station's final graph, after --count updates, at --timeout, or at
// SIGINT/SIGTERM. With --spark it subscribes to a Spark-DSG publisher instead (a Hydra robot, or
// station --spark-publish) and takes each whole graph in Spark-DSG's wire form; it also ends
// --idle seconds after the last graph; an --out .sparkdsg then gets the last message as it came,
// behind Spark-DSG's file header.

#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/stop_signals.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/io/spark_graph.h"
#include "hydra_multi/net/fused_graph.h"
#include "hydra_multi/net/spark_publisher.h"

namespace hydra_multi::apps {

namespace {

// Written beside, then renamed: a reader never sees half a graph.
// Written beside and renamed, so that a reader never sees half a file.
Status replaceWith(const std::string& out, const std::function<Status(const std::string&)>& write) {
  const std::string partial = out + ".partial" + std::filesystem::path(out).extension().string();
  if (Status s = write(partial); !s) return s;
  std::error_code ec;
  std::filesystem::rename(partial, out, ec);
  if (ec) return Error{out + ": " + ec.message()};
  return Status::Ok();
}

Status writeLatest(const std::string& out, const SceneGraph& graph) {
  return replaceWith(out, [&](const std::string& path) { return io::saveSceneGraph(path, graph); });
}

Status writeLatestBytes(const std::string& out, const std::string& bytes) {
  return replaceWith(out, [&](const std::string& path) { return io::writeFile(path, bytes); });
}

int watchSpark(const WatchOptions& o) {
  using Clock = std::chrono::steady_clock;
  auto sub = net::SparkSubscriber::create(o.connect);
  if (!sub) return fail("--connect " + sub.error());
  const StopSignals signals;
  const Clock::time_point start = Clock::now();
  Clock::time_point last = start;
  size_t graphs = 0, refused = 0;
  const auto seconds = [](Clock::time_point since) {
    return std::chrono::duration<double>(Clock::now() - since).count();
  };
  while (!StopSignals::requested() && !(o.count > 0 && graphs >= o.count) &&
         !(o.timeout_s > 0.0 && seconds(start) >= o.timeout_s) &&
         !(o.idle_s > 0.0 && graphs > 0 && seconds(last) >= o.idle_s)) {
    const std::optional<std::string> message = sub.value()->receive(std::chrono::milliseconds(100));
    if (!message) continue;
    auto wire = io::spark::decodeWire(*message, *io::spark::Version::parse(o.spark_version));
    auto imported =
        wire ? io::sceneGraphFromSpark(wire.value()) : Result<io::SparkImport>(Error{wire.error()});
    if (!imported) {
      ++refused;
      std::cerr << "watch: a message of " << message->size()
                << " bytes is not a graph: " << imported.error() << std::endl;
      continue;
    }
    ++graphs;
    last = Clock::now();
    const SceneGraph& graph = imported.value().graph;
    std::cout << "spark graph " << graphs << ": " << graph.numNodes() << " nodes, "
              << graph.numEdges() << " edges, mesh " << graph.mesh().vertices.size()
              << " vertices, " << message->size() << " bytes" << std::endl;
    for (const auto& [what, n] : imported.value().left_out)
      std::cerr << "watch: left out " << n << " " << what << std::endl;
    if (!o.out.empty()) {
      // A .sparkdsg gets the message as it came, behind the file header: Spark-DSG loads it.
      const Status s = io::formatFromPath(o.out) == io::FileFormat::kSparkBinary
                           ? writeLatestBytes(o.out, io::spark::encodeFileHeader() + *message)
                           : writeLatest(o.out, graph);
      if (!s) return fail(s.message());
    }
  }
  std::cerr << "watch: " << graphs << " Spark-DSG graphs"
            << (refused ? ", " + std::to_string(refused) + " messages refused" : "")
            << (o.out.empty() ? std::string() : "; latest graph in " + o.out) << std::endl;
  return 0;
}

}  // namespace

int runWatch(const WatchOptions& o) {
  if (o.spark) return watchSpark(o);
  using Clock = std::chrono::steady_clock;
  net::GraphWatcherOptions options;
  options.connect = o.connect;
  if (!o.quiet) options.log = [](const std::string& line) { std::cerr << line << std::endl; };
  net::GraphWatcher watcher(options);
  const Clock::time_point start = Clock::now();
  size_t updates = 0;
  Status written = Status::Ok();
  const StopSignals signals;
  const auto each = [&](const net::WatchState& state) {
    ++updates;
    std::cout << net::describeFused(state.summary()) << std::endl;
    if (!o.out.empty() && written.ok()) written = writeLatest(o.out, state.graph());
  };
  Status status = Status::Ok();
  while (status.ok() && written.ok() && !StopSignals::requested() && !watcher.ended() &&
         !(o.count > 0 && updates >= o.count) &&
         !(o.timeout_s > 0.0 &&
           std::chrono::duration<double>(Clock::now() - start).count() >= o.timeout_s))
    status = watcher.pump(std::chrono::milliseconds(100), each);
  if (!status.ok()) return fail(status.message());
  if (!written.ok()) return fail(written.message());
  std::cerr << "watch: " << updates << " fused updates (" << watcher.snapshots() << " snapshots, "
            << watcher.deltas() << " deltas)"
            << (watcher.ended() ? ", the station's final graph" : "")
            << (o.out.empty() ? std::string() : "; latest graph in " + o.out) << std::endl;
  return 0;
}

}  // namespace hydra_multi::apps
