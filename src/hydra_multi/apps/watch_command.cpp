// `hydra-multi watch --connect ENDPOINT [--out FILE] [--count N] [--timeout S]`: a subscriber of
// a station's fused graph (station --publish; net/fused_graph.h). It asks for a snapshot, then
// takes the deltas; a gap asks for a snapshot again. One line per fused update on stdout
// (sequence, round, nodes per layer, robots aligned); with --out, the latest graph written after
// every update. Ends at the station's final graph, after --count updates, at --timeout, or at
// SIGINT/SIGTERM.

#include <chrono>
#include <filesystem>
#include <iostream>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/stop_signals.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/net/fused_graph.h"

namespace hydra_multi::apps {

int runWatch(const WatchOptions& o) {
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
    if (!o.out.empty() && written.ok()) {
      // Written beside, then renamed: a reader never sees half a graph.
      const std::string partial =
          o.out + ".partial" + std::filesystem::path(o.out).extension().string();
      written = io::saveSceneGraph(partial, state.graph());
      std::error_code ec;
      if (written.ok()) std::filesystem::rename(partial, o.out, ec);
      if (ec) written = Error{o.out + ": " + ec.message()};
    }
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
