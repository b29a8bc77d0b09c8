// `hydra-multi station --listen ENDPOINT --out DIR [--config FILE] [--expect-robots N]`: the
// station as a service. Robots connect over ZeroMQ (net/station_server.h, docs/PROTOCOL.md) and
// stream their updates; the station runs until SIGINT or SIGTERM, or until N robots have said BYE,
// then runs its last backend round and writes what `run` writes but the ground truth's verdicts
// (the station never reads ground truth: `evaluate --dataset D --result DIR/graph.json` does),
// plus DIR/station.json (what became of every robot's messages and updates) and DIR/endpoint (the
// endpoint bound, written as soon as it is: a ':*' port picks a free one).
// Every update it accepts goes to DIR/journal.sqlite (store/journal.h) before it is acknowledged;
// started on a DIR that holds a journal, the station first replays it, so that a station that was
// killed loses nothing it acknowledged and its robots resend only the rest.
// `--spark-robot NAME=tcp://HOST:PORT` adds Hydra robots (net/hydra_robots.h): their whole graphs
// become robot NAME's updates, journaled as the others (epoch 0, the graph's bytes as the
// message's); after a restart each one's next graph goes whole. They say no BYE: with
// `--spark-done-after S` one silent for S s after a graph counts as done for --expect-robots.

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/load_sampler.h"
#include "hydra_multi/apps/run_viewer.h"
#include "hydra_multi/apps/station_outputs.h"
#include "hydra_multi/apps/stop_signals.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/net/fused_graph.h"
#include "hydra_multi/net/hydra_robots.h"
#include "hydra_multi/net/keys.h"
#include "hydra_multi/net/protocol.h"
#include "hydra_multi/net/spark_publisher.h"
#include "hydra_multi/net/station_server.h"
#include "hydra_multi/station/bandwidth.h"
#include "hydra_multi/station/frontend_digest.h"
#include "hydra_multi/station/station_config.h"
#include "hydra_multi/store/journal.h"

namespace hydra_multi::apps {

int runStationCommand(const StationCommandOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return fail("cannot create " + o.out + ": " + ec.message());
  StationOptions options;
  if (!o.config.empty()) {
    if (Status s = loadStationConfig(o.config, options); !s) return fail(s.message());
  }
  const auto config = canonicalStationConfig(o.config);
  if (!config) return fail(config.error());
  const io::spark::Version spark_version = *io::spark::Version::parse(o.spark_version);
  // Whole lines on stderr, whichever thread says them: the journal's replay runs backend rounds
  // whose lines would otherwise split this thread's.
  std::mutex stderr_mutex;
  const auto say = [&stderr_mutex](const std::string& line) {
    std::lock_guard<std::mutex> lock(stderr_mutex);
    std::cerr << line + "\n" << std::flush;
  };
  const auto log = [&o, &say](const std::string& line) {
    if (!o.quiet) say(line);
  };
  options.log = log;
  if (o.order == "time") {
    options.time_order_hold_s = o.order_hold_s;
    options.expected_robots = o.expect_robots;
  }
  std::unique_ptr<net::GraphPublisher> publisher;
  if (!o.publish.empty()) {
    auto created = net::GraphPublisher::create({o.publish, log});
    if (!created) return fail("--publish " + created.error());
    publisher = std::move(created).value();
    std::ofstream(fs::path(o.out) / "publish") << publisher->endpoint() << "\n";
    say("station: publishing the fused graph: snapshots on " + publisher->endpoint() +
        ", deltas on " + publisher->publishEndpoint() + " (hydra-multi watch --connect " +
        publisher->endpoint() + ")");
  }
  // The viewer: its history always (`view OUT`), live with --http; the robots' links from the
  // server once it exists (and not after it is gone).
  std::mutex links_mutex;
  const net::StationServer* link_source = nullptr;
  const net::HydraRobots* hydra_source = nullptr;
  auto opened = RunViewer::open(
      o.out, o.http,
      [&](const RoundOutput*) {
        std::map<RobotId, web::RobotLink> links;
        std::lock_guard<std::mutex> lock(links_mutex);
        if (link_source == nullptr) return links;
        for (const auto& [robot, l] : link_source->links())
          links[robot] = {l.connected && !l.said_bye, l.silent_s, l.bytes, l.said_bye};
        if (hydra_source != nullptr) {
          for (const auto& [robot, l] : hydra_source->links())
            links[robot] = {l.connected && !l.said_bye, l.silent_s, l.bytes, l.said_bye};
        }
        return links;
      },
      o.quiet);
  if (!opened) return fail(opened.error());
  const std::unique_ptr<RunViewer> viewer = std::move(opened).value();
  if (!viewer->url().empty()) {
    std::ofstream(fs::path(o.out) / "http") << viewer->url() << "\n";
    say("station: the live viewer is at " + viewer->url());
  }
  std::unique_ptr<net::SparkPublisher> spark;
  if (!o.spark_publish.empty()) {
    auto created = net::SparkPublisher::create(o.spark_publish, !o.spark_no_mesh, spark_version);
    if (!created) return fail(created.error());
    spark = std::move(created).value();
    std::ofstream(fs::path(o.out) / "spark_publish") << spark->endpoint() << "\n";
    say("station: publishing the fused graph in Spark-DSG's wire form on " + spark->endpoint() +
        (o.spark_no_mesh ? " (without the mesh)" : ""));
  }
  options.on_round = [p = publisher.get(), v = viewer.get(),
                      s = spark.get()](const RoundOutput& out) {
    if (p != nullptr)
      p->publish(out.graph, out.timing.round, out.timing.report.robots,
                 out.timing.report.robots_aligned);
    if (s != nullptr) s->publish(out.graph);
    v->onRound(out);
  };
  Station station(options);
  net::StationServerOptions server_options;
  server_options.listen = o.listen;
  if (!o.keys.empty()) {
    if (!net::curveAvailable())
      return fail("--keys: this ZeroMQ library has no CURVE (it was built without libsodium)");
    auto robots = net::readRobotKeys(o.keys);
    if (!robots) return fail(robots.error());
    auto secret = net::readKey(o.key);
    if (!secret) return fail(secret.error());
    server_options.robot_keys = std::move(robots).value();
    server_options.secret_key = secret.value();
  }
  server_options.max_message_bytes = static_cast<size_t>(o.max_message_mb * (1 << 20));
  server_options.max_messages_per_s = o.rate_limit;
  server_options.max_bytes_per_s = o.rate_limit_mb * 1e6;
  server_options.handshake_s = o.handshake_s;
  server_options.log = log;
  net::HydraRobotsOptions hydra_options;
  for (const std::string& text : o.spark_robots) {
    auto source = net::parseHydraRobotSource(text);
    if (!source) return fail("--spark-robot " + source.error());
    server_options.other_inputs.insert(source.value().robot);
    hydra_options.robots.push_back(source.value());
  }
  const std::string journal_path = (fs::path(o.out) / "journal.sqlite").string();
  auto journal =
      store::Journal::open(journal_path, o.durability == "normal" ? store::Durability::kNormal
                                                                  : store::Durability::kFull);
  if (!journal) return fail(journal.error());
  // The server's thread and each Hydra robot's append to the one journal.
  std::mutex journal_mutex;
  const auto persist = [&journal, &journal_mutex](const RobotUpdate& u, uint64_t epoch,
                                                  const std::string& payload, size_t wire_bytes) {
    const int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::system_clock::now().time_since_epoch())
                            .count();
    std::lock_guard<std::mutex> lock(journal_mutex);
    return journal.value()->append(
        {u.robot, epoch, u.sequence, payload, now, u.is_snapshot, wire_bytes});
  };
  server_options.persist = persist;
  server_options.persist_bye = [&journal, &journal_mutex](RobotId robot, uint64_t epoch) {
    std::lock_guard<std::mutex> lock(journal_mutex);
    return journal.value()->markDone(robot, epoch);
  };
  auto server = net::StationServer::create(station, server_options);
  if (!server) return fail(server.error());
  std::unique_ptr<net::HydraRobots> hydra;
  if (!hydra_options.robots.empty()) {
    hydra_options.max_message_bytes = server_options.max_message_bytes;
    hydra_options.done_after_s = o.spark_done_after_s;
    hydra_options.version = spark_version;
    hydra_options.log = log;
    hydra_options.persist = [&persist](const RobotUpdate& u, const std::string& payload,
                                       size_t wire_bytes) {
      return persist(u, 0, payload, wire_bytes);
    };
    auto created = net::HydraRobots::create(station, hydra_options);
    if (!created) return fail(created.error());
    hydra = std::move(created).value();
  }
  // What an earlier station on this folder acknowledged, before any robot is heard.
  size_t replayed = 0, unreadable = 0;
  std::map<RobotId, uint64_t> hydra_next;  // a Hydra robot's next sequence after the journal's
  const Status read = journal.value()->replay([&](store::JournalEntry&& e) {
    auto u = io::decodeRobotUpdateBinary(e.payload);
    if (!u || u.value().robot != e.robot || u.value().sequence != e.sequence) {
      ++unreadable;
      log("station: " + journal_path + ": update " + std::to_string(e.sequence) + " of robot " +
          e.robot.str() + " does not decode; left out" + (u ? "" : ": " + u.error()));
      return;
    }
    if (hydra && hydra->has(e.robot)) {
      hydra_next[e.robot] = std::max(hydra_next[e.robot], e.sequence + 1);
    } else {
      server.value()->hold(e.robot, e.epoch, e.sequence, u.value().is_snapshot);
    }
    station.submit(std::move(u).value());
    ++replayed;
  });
  if (!read) return fail(read.message());
  // Robots that said BYE and sent nothing after it: done, as before the restart.
  auto done = journal.value()->done();
  if (!done) return fail(done.error());
  for (const auto& [robot, epoch] : done.value()) {
    server.value()->holdDone(robot, epoch);
    say("station: robot " + robot.str() + " said BYE before the restart");
  }
  if (replayed + unreadable > 0)
    say("station: resumed from " + journal_path + ": " + std::to_string(replayed) +
        " updates replayed" + (unreadable ? ", " + std::to_string(unreadable) + " left out" : ""));
  if (hydra) {
    for (const auto& [robot, next] : hydra_next) hydra->resumeAt(robot, next);
    hydra->start();
    for (const net::HydraRobotSource& r : hydra_options.robots)
      say("station: Hydra robot " + r.robot.str() + ": subscribed to " + r.endpoint);
  }
  {
    std::lock_guard<std::mutex> lock(links_mutex);
    link_source = server.value().get();
    hydra_source = hydra.get();
  }
  const std::string endpoint = server.value()->endpoint();
  std::ofstream(fs::path(o.out) / "endpoint") << endpoint << "\n";
  std::string admitted;
  for (const auto& [key, robot] : server_options.robot_keys)
    admitted += (admitted.empty() ? "" : ", ") + robot.str();
  say("station: listening on " + endpoint +
      (o.keys.empty() ? " (NO AUTHENTICATION: any peer that reaches it can speak for any robot; "
                        "give --keys and --key)"
                      : " (CURVE: robots " + admitted + " of " + o.keys + ")") +
      (o.expect_robots > 0 ? ", until " + std::to_string(o.expect_robots) + " robots have said BYE"
                           : std::string(", until SIGINT or SIGTERM")));

  // The ingest queue, memory and CPU once a second, to tell whether the station keeps up.
  auto load =
      LoadSampler::start((fs::path(o.out) / "load.csv").string(),
                         [&station] { return station.queued(); }, std::chrono::milliseconds(1000));
  if (!load) return fail(load.error());
  {
    const StopSignals signals;
    if (!hydra) {
      server.value()->serve([] { return StopSignals::requested(); }, o.expect_robots);
    } else {
      // Hydra robots say no BYE: the team is done when BYEs and Hydra robots done make it.
      const net::StationServer& s = *server.value();
      server.value()->serve([&] {
        if (StopSignals::requested()) return true;
        if (o.expect_robots == 0) return false;
        size_t done = hydra->done();
        for (const auto& [robot, l] : s.links()) done += l.said_bye ? 1 : 0;
        return done >= o.expect_robots;
      });
    }
  }
  if (hydra) hydra->stop();
  log("station: input closed; last backend round");
  const StationResult result = station.finish();
  load.value()->stop();
  if (publisher) publisher->close();        // the final graph is out; subscribers are told it is
  if (spark) spark->publish(result.graph);  // the final graph once more, as it was written
  if (Status s = viewer->finish(result.graph); !s) return fail(s.message());
  {
    std::lock_guard<std::mutex> lock(links_mutex);
    link_source = nullptr;
    hydra_source = nullptr;
  }
  if (Status s = writeStationOutputs(o.out, result); !s) return fail(s.message());
  if (Status s = writeStationLoopClosures(o.out, result); !s) return fail(s.message());
  std::ofstream(fs::path(o.out) / "config.json") << config.value() << "\n";

  // Bandwidth of every update the station holds (those of earlier runs on this folder too), from
  // the journal: its message's bytes against a full resend of the robot's map at that moment.
  const auto ledger_start = std::chrono::steady_clock::now();
  BandwidthLedger ledger(net::updateFramingBytes());
  const Status reread = journal.value()->replay([&](store::JournalEntry&& e) {
    if (auto u = io::decodeRobotUpdateBinary(e.payload)) ledger.add(u.value(), e.wire_bytes);
  });
  if (!reread) return fail(reread.message());
  auto written = writeBandwidth(o.out, ledger);
  if (!written) return fail(written.error());
  const std::map<RobotId, RobotBandwidth>& sent = written.value();
  const RobotBandwidth team = teamBandwidth(sent);
  std::ostringstream ledger_s;
  ledger_s
      << std::fixed << std::setprecision(1)
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - ledger_start).count();
  log("station: bandwidth of " + std::to_string(team.updates) + " updates against full " +
      "resends in " + ledger_s.str() + " s");

  const net::StationServerCounts& counts = server.value()->counts();
  const StationTimes times = stationTimes(result);
  nlohmann::ordered_json robots = nlohmann::ordered_json::object();
  // What a robot's updates cost, from the journal (bandwidth.csv's totals).
  const auto addBandwidth = [&sent](RobotId robot, nlohmann::ordered_json& entry) {
    if (const auto t = sent.find(robot); t != sent.end()) {
      entry["update_bytes"] = t->second.wire_bytes;
      entry["update_record_bytes"] = t->second.record_bytes;
      entry["full_resend_bytes"] = t->second.full_resend_bytes;
    }
  };
  size_t duplicates = 0;
  for (const auto& [robot, c] : counts.robots) {
    robots[robot.str()] = {{"updates", c.updates},
                           {"snapshots", c.snapshots},
                           {"snapshots_requested", c.snapshots_requested},
                           {"duplicates", c.duplicates},
                           {"connections", c.connections},
                           {"bytes", c.bytes},
                           {"said_bye", c.said_bye},
                           {"next_sequence", c.next_sequence}};
    addBandwidth(robot, robots[robot.str()]);
    duplicates += c.duplicates;
  }
  size_t hydra_graphs = 0, hydra_bytes = 0, hydra_refused = 0;
  if (hydra) {
    for (const auto& [robot, c] : hydra->counts()) {
      nlohmann::ordered_json entry = {{"input", "hydra"},
                                      {"graphs", c.graphs},
                                      {"bytes", c.bytes},
                                      {"overtaken", c.overtaken},
                                      {"refused", c.refused},
                                      {"unchanged", c.unchanged},
                                      {"updates", c.updates},
                                      {"snapshots", c.snapshots},
                                      {"next_sequence", c.next_sequence},
                                      {"last_graph_bytes", c.last_bytes}};
      addBandwidth(robot, entry);
      robots[robot.str()] = entry;
      hydra_graphs += c.graphs;
      hydra_bytes += c.bytes;
      hydra_refused += c.refused;
    }
  }
  size_t late = 0;
  for (const auto& [robot, n] : result.late) late += n;
  const nlohmann::ordered_json summary = {{"endpoint", endpoint},
                                          {"robots", result.robots},
                                          {"robots_aligned", result.aligned.size()},
                                          {"global_frame_robot", result.global_robot.str()},
                                          {"updates_applied", result.counts.appliedTotal()},
                                          {"updates_duplicate", duplicates},
                                          {"updates_refused", counts.refused},
                                          {"updates_rejected", result.counts.rejected},
                                          {"updates_behind_gap", result.counts.behindGap()},
                                          {"snapshots_requested", counts.snapshots_requested},
                                          {"updates_superseded", result.counts.superseded},
                                          {"updates_late", late},
                                          {"bytes_received", counts.bytes + hydra_bytes},
                                          {"update_bytes", team.wire_bytes},
                                          {"update_record_bytes", team.record_bytes},
                                          {"full_resend_bytes", team.full_resend_bytes},
                                          {"full_resend_ratio", fullResendRatio(team)},
                                          {"updates_without_full_resend", team.without_full_resend},
                                          {"journal", journal_path},
                                          {"journal_entries", journal.value()->size()},
                                          {"journal_integrity", journal.value()->integrityCheck()},
                                          {"updates_replayed", replayed},
                                          {"backend_rounds", result.rounds.size()},
                                          {"frontend_ms_p50", times.frontend_ms_p50},
                                          {"backend_ms_p50", times.backend_ms_p50},
                                          {"backend_ms_max", times.backend_ms_max},
                                          {"backend_last_ms", times.backend_last_ms},
                                          {"peak_memory_mb", times.peak_memory_mb},
                                          {"frontend_digest", digestHex(result.frontend_digest)},
                                          {"per_robot", robots}};
  std::ofstream(fs::path(o.out) / "station.json") << summary.dump(2) << "\n";
  size_t refused = 0;
  for (const auto& [reason, n] : counts.refused) refused += n;
  std::cout
      << std::fixed << std::setprecision(2) << "station on " << endpoint << ": " << result.robots
      << " robots, " << result.rounds.size() << " backend rounds, " << result.wall_s << " s\n"
      << "  updates               " << describeUpdates(result.counts, 0) << "\n"
      << (late > 0 ? "  time order            " + std::to_string(late) +
                         " updates late (after updates of later robot time), the map may differ "
                         "from run's\n"
                   : std::string())
      << "  messages              " << counts.bytes << " bytes, " << duplicates
      << " updates resent and held already, " << refused << " refused\n"
      << (hydra ? "  Hydra robots          " + std::to_string(hydra_graphs) + " graphs, " +
                      std::to_string(hydra_bytes) + " bytes, " + std::to_string(hydra_refused) +
                      " refused\n"
                : std::string())
      << "  bandwidth             " << team.wire_bytes << " bytes of updates on the wire, "
      << team.record_bytes << " uncompressed; as full resends " << team.full_resend_bytes
      << " bytes uncompressed, " << std::setprecision(1) << fullResendRatio(team)
      << " times more (bandwidth.csv, bandwidth.svg)\n"
      << std::setprecision(2) << "  robots aligned        " << result.aligned.size() << " of "
      << result.robots << "; global frame: robot " << result.global_robot.str() << "'s\n"
      << "outputs in " << o.out
      << ": graph.json, graph.spark.json, mesh.ply, timing.csv, loop_closures.csv, config.json, "
         "station.json, bandwidth.csv, bandwidth.svg, load.csv, journal.sqlite\n";
  return 0;
}

}  // namespace hydra_multi::apps

namespace hydra_multi::apps {

int runKeygen(const KeygenOptions& o) {
  auto keys = net::generateKeyPair();
  if (!keys) return fail(keys.error());
  if (Status s = net::writeKeyPair(o.out, keys.value()); !s) return fail(s.message());
  std::cout << "wrote " << o.out << ".key (secret: keep it on its machine) and " << o.out
            << ".pub (public: give it to the station, or to the robots for the station's key)\n";
  return 0;
}

}  // namespace hydra_multi::apps
