// hydra-multi: the command line. It only parses options into the commands' option structs.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <limits>
#include <string>
#include <thread>

#include "hydra_multi/apps/command_line.h"
#include "hydra_multi/apps/commands.h"
#include "hydra_multi/core/robot_id.h"
#include "hydra_multi/core/version.h"
#include "hydra_multi/net/hydra_robots.h"

int main(int argc, char** argv) {
  using namespace hydra_multi::apps;
  CLI::App app{
      "hydra-multi: one 3D scene graph of a building from a team of robots (Hydra-Multi).\n"
      "File formats, chosen by extension: .json (ours), .spark.json (Spark-DSG), .dsgb (binary),\n"
      ".sparkdsg (Spark-DSG binary, format 1.1.3),\n"
      ".ply (mesh, write only). A .json file in Spark-DSG's layout is recognised by its content."};
  app.set_version_flag("--version", std::string("hydra-multi ") + hydra_multi::kVersion);
  app.require_subcommand(1);
  app.footer(
      "Errors go to stderr as 'hydra-multi: error: <what and where>'. Exit codes: 0 success; 1 a\n"
      "failure (a missing, unreadable or malformed file, a failed run); 2 a wrong command line "
      "(an\n"
      "unknown command or option, a missing or out-of-range value).");
  CommandLine cli(app);
  constexpr double kMax = std::numeric_limits<double>::max();
  constexpr uint64_t kAnySeed = std::numeric_limits<uint64_t>::max();

  InfoOptions info;
  CLI::App* info_cmd = app.add_subcommand(
      "info", "Counts per layer and per robot of a scene graph or update stream");
  cli.inputFile(info_cmd, "file", info.path,
                "scene graph (.json, .spark.json, .dsgb, .sparkdsg) or update stream")
      ->required();
  info_cmd->add_flag("--json", info.json, "print exactly one JSON object on stdout");

  ConvertOptions convert;
  CLI::App* convert_cmd =
      app.add_subcommand("convert", "Convert a scene graph between formats (by extension)");
  cli.inputFile(convert_cmd, "input", convert.input,
                "input graph (.json, .spark.json, .dsgb, .sparkdsg)")
      ->required();
  cli.outputFile(convert_cmd, "output", convert.output,
                 "output (.json, .spark.json, .dsgb, .sparkdsg, .ply)")
      ->required();

  PgoOptions pgo;
  pgo.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  CLI::App* pgo_cmd = app.add_subcommand(
      "pgo", "Pose-graph optimization of g2o/TORO files (robust, multi-robot, evaluated)");
  cli.inputFiles(pgo_cmd, "--input", pgo.inputs,
                 "g2o/TORO file; repeat to merge (duplicates count once)")
      ->required();
  CLI::Option* unknown_frames = pgo_cmd->add_flag(
      "--unknown-frames", pgo.unknown_frames,
      "each input is a robot of unknown frame: align by robust pose averaging (replaces --init)");
  pgo_cmd->add_option("--residual", pgo.residual, "geodesic (SE(3) log) or chordal (SE-Sync cost)")
      ->check(CLI::IsMember({"geodesic", "chordal"}))
      ->capture_default_str();
  pgo_cmd->add_option("--init", pgo.init, "odometry or chordal")
      ->check(CLI::IsMember({"odometry", "chordal"}))
      ->capture_default_str()
      ->excludes(unknown_frames);
  pgo_cmd->add_option("--robust", pgo.robust, "none or gnc (GNC-TLS over loop closures)")
      ->check(CLI::IsMember({"none", "gnc"}))
      ->capture_default_str();
  CLI::Option* outliers =
      cli.real(pgo_cmd, "--outliers", pgo.outliers,
               "inject outliers: their share of all loop closures", {0.0, 0.99});
  CLI::Option* pgo_seed = cli.integer(pgo_cmd, "--seed", pgo.seed, "seed of the outlier injection",
                                      uint64_t{0}, kAnySeed)
                              ->capture_default_str();
  CLI::Option* inliers_xml = cli.inputFile(pgo_cmd, "--inliers-xml", pgo.inliers_xml,
                                           "gt_info.xml: 1-based inlier edge numbers");
  cli.inputFile(pgo_cmd, "--inlier-edges", pgo.inlier_edges,
                "labels: g2o file whose edges are the true loop closures")
      ->excludes(inliers_xml);
  cli.integer(pgo_cmd, "--min-inliers", pgo.min_inliers,
              "k: inlier loop closures a robot pair needs to be aligned", size_t{1},
              size_t{1000000})
      ->capture_default_str();
  CLI::Option* linear_solver =
      pgo_cmd
          ->add_option(
              "--linear-solver", pgo.linear_solver,
              "GNC solves: auto (Cholesky unless a factorization takes > 2 MFLOP per pose), "
              "cholesky, cg")
          ->check(CLI::IsMember({"auto", "cholesky", "cg"}))
          ->capture_default_str();
  CLI::Option* gnc_inner =
      cli.integer(pgo_cmd, "--gnc-inner-iterations", pgo.gnc_inner_iterations,
                  "Levenberg-Marquardt iterations per GNC solve (0: up to 100)", 0, 1000)
          ->capture_default_str();
  CLI::Option* keep_chains = pgo_cmd->add_flag(
      "--keep-chains", pgo.keep_chains,
      "GNC solves over every pose instead of chains of two-edge poses reduced to one edge");
  cli.inputFile(pgo_cmd, "--groundtruth", pgo.groundtruth,
                "true poses (g2o vertices or TORO edges)");
  cli.outputFile(pgo_cmd, "--output", pgo.output, "write the optimized graph (g2o)");
  pgo_cmd->add_flag("--json", pgo.json, "print exactly one JSON object on stdout");
  pgo_cmd->add_flag("--skip-bad-lines", pgo.skip_bad_lines, "report malformed lines and go on");
  cli.real(pgo_cmd, "--tolerance", pgo.tolerance, "relative cost change that ends a solve",
           {0.0, 1.0, true, true})
      ->capture_default_str();
  cli.integer(pgo_cmd, "--threads", pgo.threads, "solver threads", 1, 1024)->capture_default_str();
  pgo_cmd->add_flag("--quiet", pgo.quiet, "no progress lines on stderr");

  AteOptions ate;
  CLI::App* ate_cmd = app.add_subcommand(
      "ate", "Absolute trajectory error after SE(3) alignment (KITTI or TUM trajectories)");
  cli.inputFile(ate_cmd, "--est", ate.estimate, "estimated trajectory")->required();
  cli.inputFile(ate_cmd, "--gt", ate.reference, "reference trajectory")->required();
  ate_cmd->add_option("--format", ate.format, "kitti (pose per line) or tum (associated by time)")
      ->check(CLI::IsMember({"kitti", "tum"}))
      ->capture_default_str();
  CLI::Option* max_time_difference =
      cli.real(ate_cmd, "--max-time-difference", ate.max_time_difference,
               "TUM: largest stamp difference of an associated pair (s)", {0.0, kMax, true})
          ->capture_default_str();
  ate_cmd->add_flag("--json", ate.json, "print exactly one JSON object on stdout");

  SimulateOptions simulate;
  CLI::App* simulate_cmd = app.add_subcommand(
      "simulate", "Generate a simulated robot-team dataset: update streams and ground truth");
  simulate_cmd
      ->add_option("--preset", simulate.preset,
                   "office-3, residence-3f, dorm-2, dorm-2-meet, hetero-2 or tiny")
      ->capture_default_str();
  cli.integer(simulate_cmd, "--seed", simulate.seed, "everything follows from it", uint64_t{0},
              kAnySeed)
      ->capture_default_str();
  cli.outputDirectory(simulate_cmd, "--out", simulate.out, "dataset directory (created)")
      ->required();
  cli.integer(simulate_cmd, "--robots", simulate.robots, "team size (default: the preset's)", 1,
              20);
  cli.real(simulate_cmd, "--scale", simulate.scale, "rooms along the corridor, times S",
           {0.25, 4.0})
      ->capture_default_str();
  cli.real(simulate_cmd, "--label-confusion", simulate.label_confusion,
           "chance that a robot labels an object as its look-alike class (default: the "
           "preset's, 0.1; 0 as with ground-truth segmentation)",
           {0.0, 1.0});
  cli.integer(simulate_cmd, "--snapshot-every", simulate.snapshot_every,
              "every N-th update of a robot is its whole map, so a station that lost an "
              "update recovers (0: only the first)",
              size_t{0}, size_t{1000000})
      ->capture_default_str();
  simulate_cmd->add_flag("--no-keypoints", simulate.no_keypoints,
                         "robots send no keypoints with their keyframes (as Hydra robots)");
  simulate_cmd->add_flag("--no-own-loop-closures", simulate.no_own_loop_closures,
                         "robots send no loop closures of their own (as Hydra robots)");
  simulate_cmd->add_flag("--quiet", simulate.quiet, "no progress lines on stderr");

  EvaluateOptions evaluate;
  CLI::App* evaluate_cmd = app.add_subcommand(
      "evaluate", "Score a scene graph (global frame = robot 0's) against a dataset's truth");
  cli.inputDirectory(evaluate_cmd, "--dataset", evaluate.dataset,
                     "dataset directory (from simulate)")
      ->required();
  cli.inputFile(evaluate_cmd, "--result", evaluate.result,
                "scene graph (.json, .spark.json, .dsgb)")
      ->required();
  evaluate_cmd->add_flag("--json", evaluate.json, "print exactly one JSON object on stdout");
  cli.outputFile(evaluate_cmd, "--objects", evaluate.objects_csv,
                 "write every estimated object's verdict (correct, duplicate, wrong_label, "
                 "misplaced) to this CSV file");
  cli.outputFile(evaluate_cmd, "--keyframes", evaluate.keyframes_csv,
                 "write every keyframe's position, true position and error (after the ATE's "
                 "fit) to this CSV file");

  DatasetGraphOptions dataset_graph;
  CLI::App* dataset_graph_cmd = app.add_subcommand(
      "dataset-graph", "One robot's final graph from a dataset's stream, in the robot's frame");
  cli.inputDirectory(dataset_graph_cmd, "--dataset", dataset_graph.dataset, "dataset directory")
      ->required();
  dataset_graph_cmd->add_option("--robot", dataset_graph.robot, "robot letter (a, b, ...) or index")
      ->required();
  cli.outputFile(dataset_graph_cmd, "--out", dataset_graph.out,
                 "graph file (.json, .dsgb, .ply, ...)")
      ->required();

  DetectOptions detect;
  CLI::App* detect_cmd = app.add_subcommand(
      "detect", "The frontend alone over a dataset: processor and loop-closure detection, timed");
  cli.inputDirectory(detect_cmd, "--dataset", detect.dataset, "dataset directory (from simulate)")
      ->required();
  detect_cmd->add_flag("--json", detect.json, "print exactly one JSON object on stdout");
  detect_cmd->add_flag("--quiet", detect.quiet, "no progress lines on stderr");
  cli.outputFile(detect_cmd, "--loop-closures", detect.loop_closures_csv,
                 "write every detected loop closure to this CSV file, with its error against "
                 "the ground truth");

  RunOptions run;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "The station over a dataset: frontend and backend threads, outputs and metrics");
  cli.inputDirectory(run_cmd, "--dataset", run.dataset, "dataset directory (from simulate)")
      ->required();
  cli.outputDirectory(run_cmd, "--out", run.out, "output directory (created)")->required();
  cli.real(run_cmd, "--speed", run.speed,
           "replay speed: 1 real time, 10 faster, 0 as fast as possible", {0.0, 1000.0})
      ->capture_default_str();
  CLI::Option* ablation =
      run_cmd
          ->add_option("--ablation", run.ablation,
                       "full: the whole system; no-ia: without initial alignment; no-rec: without "
                       "reconciliation (merges)")
          ->check(CLI::IsMember({"full", "no-ia", "no-rec"}))
          ->capture_default_str();
  run_cmd
      ->add_option("--baseline", run.baseline,
                   "instead of the full system (evaluation only, they read ground truth or skip "
                   "steps): gt-align: single-robot graphs placed by the true start poses; "
                   "hm-align: single-robot graphs placed by our initial alignment; oracle-lc: the "
                   "full system fed only the correct inter-robot loop closures")
      ->check(CLI::IsMember({"gt-align", "hm-align", "oracle-lc"}))
      ->excludes(ablation);
  cli.inputFile(run_cmd, "--config", run.config,
                "station configuration (JSON; README lists the keys)");
  run_cmd->add_flag("--quiet", run.quiet, "no progress lines on stderr");
  run_cmd->add_option("--http", run.http,
                      "serve the live viewer on HOST:PORT while the run lasts (port 0: a free one; "
                      "the URL is printed)");

  StationCommandOptions station;
  CLI::App* station_cmd = app.add_subcommand(
      "station", "The station as a service: robots stream to it over ZeroMQ (docs/PROTOCOL.md)");
  station_cmd
      ->add_option("--listen", station.listen,
                   "ZeroMQ endpoint to bind (a port of '*' picks a free one; the bound endpoint "
                   "is written to OUT/endpoint)")
      ->capture_default_str();
  cli.outputDirectory(station_cmd, "--out", station.out, "output directory (created)")->required();
  cli.inputFile(station_cmd, "--config", station.config,
                "station configuration (JSON; README lists the keys)");
  cli.integer(station_cmd, "--expect-robots", station.expect_robots,
              "end once this many robots have said BYE (0: run until SIGINT or SIGTERM)", size_t{0},
              size_t{hydra_multi::RobotId::kMaxRobots})
      ->capture_default_str();
  cli.real(station_cmd, "--max-message-mb", station.max_message_mb, "larger messages are refused",
           {0.0, 4096.0, true})
      ->capture_default_str();
  cli.real(station_cmd, "--rate-limit", station.rate_limit,
           "messages per second a connection may send (bursts of two seconds' worth); more are "
           "dropped unanswered until it slows down (0: no limit)",
           {0.0, 1e9})
      ->capture_default_str();
  cli.real(station_cmd, "--rate-limit-mb", station.rate_limit_mb,
           "the same in MB per second (0: no limit)", {0.0, 1e6})
      ->capture_default_str();
  cli.real(station_cmd, "--handshake-s", station.handshake_s,
           "a connection that has not completed ZeroMQ's handshake within this time is closed",
           {0.001, 3600.0})
      ->capture_default_str();
  station_cmd
      ->add_option("--durability", station.durability,
                   "the journal's SQLite synchronous setting: full (every commit synced) or normal "
                   "(synced at checkpoints: survives a crash of the station, not of the machine)")
      ->check(CLI::IsMember({"full", "normal"}))
      ->capture_default_str();
  station_cmd
      ->add_option("--order", station.order,
                   "arrival: the frontend takes updates as they arrive; time: in robot time, as "
                   "run replays a dataset (the map does not depend on the network's timing; each "
                   "update held at most --order-hold s, the team being --expect-robots robots)")
      ->check(CLI::IsMember({"arrival", "time"}))
      ->capture_default_str();
  CLI::Option* order_hold = cli.real(station_cmd, "--order-hold", station.order_hold_s,
                                     "with --order time: the longest an update waits for the "
                                     "other robots (s)",
                                     {0.0, 3600.0, true});
  order_hold->capture_default_str();
  CLI::Option* station_keys = cli.inputDirectory(
      station_cmd, "--keys", station.keys,
      "admit only the robots whose public keys lie here (a.pub, b.pub, ...; CURVE)");
  cli.inputFile(station_cmd, "--key", station.key, "the station's secret key (with --keys)")
      ->needs(station_keys);
  station_keys->needs(station_cmd->get_option("--key"));
  station_cmd->add_flag("--quiet", station.quiet, "no progress lines on stderr");

  station_cmd->add_option(
      "--publish", station.publish,
      "publish the fused graph after every backend round (ZeroMQ clone pattern: "
      "snapshots on this endpoint, deltas on its port + 1; `watch` subscribes)");
  station_cmd->add_option("--http", station.http,
                          "serve the live viewer on HOST:PORT (port 0: a free one; the URL is "
                          "printed and written to OUT/http)");
  CLI::Option* spark_publish = station_cmd->add_option(
      "--spark-publish", station.spark_publish,
      "bind a PUB here and send the fused graph after every backend round in Spark-DSG's wire "
      "form (format 1.1.3), as Spark-DSG's ZmqSender does: Hydra's tools and Spark-DSG's "
      "ZmqReceiver read it");
  station_cmd
      ->add_flag("--spark-no-mesh", station.spark_no_mesh,
                 "with --spark-publish: leave the mesh out")
      ->needs(spark_publish);
  CLI::Option* spark_robot =
      station_cmd
          ->add_option("--spark-robot", station.spark_robots,
                       "a Hydra robot, NAME=tcp://HOST:PORT (repeatable): connect a SUB to its "
                       "ZmqSink and take each whole graph it publishes (Spark-DSG's wire form, "
                       "format 1.1.3) as robot NAME's update")
          ->check([](const std::string& text) {
            auto source = hydra_multi::net::parseHydraRobotSource(text);
            return source ? std::string() : source.error();
          });
  cli.real(station_cmd, "--spark-done-after", station.spark_done_after_s,
           "a Hydra robot that sent a graph and then nothing for this many seconds is done, as "
           "if it said BYE (Hydra robots say none; 0: never)",
           {0.0, 86400.0})
      ->needs(spark_robot)
      ->capture_default_str();
  const auto spark_version_check = [](const std::string& text) {
    const auto version = hydra_multi::io::spark::Version::parse(text);
    if (!version) return "'" + text + "' is not a version (MAJOR.MINOR.PATCH, e.g. 1.1.3)";
    return hydra_multi::io::spark::unsupported(*version);
  };
  station_cmd
      ->add_option("--spark-version", station.spark_version,
                   "the Spark-DSG format (1.0.2 to 1.1.4) of the Hydra robots' graphs and of "
                   "--spark-publish: their Spark-DSG's version (Hydra main: 1.1.3)")
      ->check(spark_version_check)
      ->capture_default_str();
  ViewOptions view;
  CLI::App* view_cmd = app.add_subcommand(
      "view", "Serve the viewer of a finished run (run's or station's output folder)");
  cli.inputDirectory(view_cmd, "dir", view.dir, "the output folder")->required();
  view_cmd->add_option("--http", view.http, "HOST:PORT to serve on (port 0: a free one)")
      ->capture_default_str();
  cli.inputDirectory(view_cmd, "--page", view.page,
                     "the built viewer page (default: BUILD/web beside the binary)");
  cli.real(view_cmd, "--replay", view.replay_s,
           "play the history as if live, one backend round every this many seconds", {0.0, 3600.0});
  view_cmd->add_flag("--quiet", view.quiet, "no progress lines on stderr");
  WatchOptions watch;
  CLI::App* watch_cmd = app.add_subcommand(
      "watch", "Subscribe to a station's fused graph (station --publish): one line per update");
  watch_cmd->add_option("--connect", watch.connect, "the station's --publish endpoint")->required();
  cli.outputFile(watch_cmd, "--out", watch.out,
                 "write the latest graph here after every update (.json, .dsgb, .spark.json, "
                 ".sparkdsg; with --spark a .sparkdsg holds the message as it came)");
  cli.integer(watch_cmd, "--count", watch.count,
              "end after this many fused updates (0: at the station's final graph)", size_t{0},
              size_t{1000000000})
      ->capture_default_str();
  cli.real(watch_cmd, "--timeout", watch.timeout_s, "end after this many seconds (0: no limit)",
           {0.0, 31536000.0})
      ->capture_default_str();
  CLI::Option* watch_spark = watch_cmd->add_flag(
      "--spark", watch.spark,
      "--connect names a Spark-DSG publisher (a Hydra robot's ZmqSink, station --spark-publish): "
      "take its whole graphs in Spark-DSG's wire form");
  cli.real(watch_cmd, "--idle", watch.idle_s,
           "with --spark: end once nothing came for this many seconds after a graph",
           {0.0, 86400.0})
      ->needs(watch_spark);
  watch_cmd
      ->add_option("--spark-version", watch.spark_version,
                   "with --spark: the publisher's Spark-DSG format (1.0.2 to 1.1.4)")
      ->check(spark_version_check)
      ->needs(watch_spark)
      ->capture_default_str();
  watch_cmd->add_flag("--quiet", watch.quiet, "no progress lines on stderr");

  KeygenOptions keygen;
  CLI::App* keygen_cmd = app.add_subcommand(
      "keygen", "Make a CURVE key pair for a robot or the station: PREFIX.key and PREFIX.pub");
  cli.outputFile(keygen_cmd, "--out", keygen.out,
                 "PREFIX of the files (a robot's is named by the robot: keys/a)")
      ->required();

  RobotCommandOptions robot;
  CLI::App* robot_cmd = app.add_subcommand(
      "robot", "Play one robot of a recorded dataset as a live robot streaming to a station");
  CLI::Option* robot_dataset =
      cli.inputDirectory(robot_cmd, "--dataset", robot.dataset,
                         "dataset directory (from simulate); required but with --graph");
  CLI::Option* robot_name = robot_cmd->add_option(
      "--robot", robot.robot, "robot letter (a, b, ...); required but with --graph");
  CLI::Option* robot_connect =
      robot_cmd->add_option("--connect", robot.connect,
                            "the station's endpoint (tcp://HOST:PORT); required without --spark");
  cli.real(robot_cmd, "--speed", robot.speed,
           "robot time: 1 real time, 10 faster, 0 as fast as the station acknowledges",
           {0.0, 1000.0})
      ->capture_default_str();
  cli.real(robot_cmd, "--timeout", robot.timeout_s,
           "give up (exit 1) when the station has not taken every update this many seconds after "
           "the last one is due (with --speed 0: after the start)",
           {0.0, 86400.0, true})
      ->capture_default_str();
  CLI::Option* robot_key =
      cli.inputFile(robot_cmd, "--key", robot.key, "the robot's secret key (CURVE)");
  cli.inputFile(robot_cmd, "--station-key", robot.station_key,
                "the station's public key (with --key)")
      ->needs(robot_key);
  robot_key->needs(robot_cmd->get_option("--station-key"));
  cli.real(robot_cmd, "--mission-start", robot.mission_start_s,
           "the mission's start (Unix time, s): the first update is due then, and those due "
           "before this process started are the robot's map already (a restarted robot: sent as "
           "a snapshot when the station asks); needs --speed above 0",
           {0.0, 1e11});
  robot_cmd->add_flag("--full-resend", robot.full_resend,
                      "send the robot's whole map every update, as the paper's robots do");
  robot_cmd
      ->add_option("--compress", robot.compress,
                   "zstd: compress payloads when the station takes it; none: never")
      ->check(CLI::IsMember({"zstd", "none"}))
      ->capture_default_str();
  CLI::Option* robot_spark = robot_cmd->add_flag(
      "--spark", robot.spark,
      "speak as a Hydra robot: publish the robot's whole graph in Spark-DSG's wire form after "
      "every update on a PUB bound at --bind, as Hydra's ZmqSink does; needs --speed above 0");
  robot_cmd->add_option("--bind", robot.bind, "with --spark: the PUB's endpoint (tcp://HOST:PORT)")
      ->needs(robot_spark);
  robot_spark->excludes(robot_connect);
  CLI::Option* robot_graph =
      cli.inputFile(robot_cmd, "--graph", robot.graph,
                    "with --spark: publish this graph file (any format info reads) every --every "
                    "s instead of a dataset's robot, as a Hydra robot whose map no longer changes");
  robot_graph->needs(robot_spark)->excludes(robot_dataset)->excludes(robot_name);
  cli.real(robot_cmd, "--every", robot.every_s, "with --graph: seconds between graphs",
           {0.001, 3600.0})
      ->needs(robot_graph)
      ->capture_default_str();
  cli.integer(robot_cmd, "--count", robot.count,
              "with --graph: publish this many graphs, then stop (0: until SIGINT or SIGTERM)",
              size_t{0}, size_t{1000000})
      ->needs(robot_graph)
      ->capture_default_str();
  std::string move_text;
  robot_cmd
      ->add_option("--move", move_text,
                   "with --spark: X,Y,Z,YAW_DEG: publish the graph as a robot whose odometric "
                   "frame is turned by YAW_DEG about z and offset by X,Y,Z m would have mapped it "
                   "(its true frame unknown to the station)")
      ->check([](const std::string& text) {
        auto move = hydra_multi::apps::parseMove(text);
        return move ? std::string() : move.error();
      })
      ->needs(robot_spark);
  robot_cmd
      ->add_option("--spark-version", robot.spark_version,
                   "with --spark: the Spark-DSG format (1.0.2 to 1.1.4) to publish in")
      ->check(spark_version_check)
      ->needs(robot_spark)
      ->capture_default_str();
  robot_cmd->add_flag("--quiet", robot.quiet, "no progress lines on stderr");

  TrialsOptions trials;
  std::string seeds = "1-5";
  constexpr uint64_t kMaxSeeds = 1000;
  CLI::App* trials_cmd = app.add_subcommand(
      "trials", "The paper's evaluation: every method on every seed of a preset, table and plots");
  trials_cmd->add_option("--preset", trials.preset, "simulated preset (see simulate)")->required();
  trials_cmd
      ->add_option("--seeds", seeds,
                   "seeds A-B (or one seed), at most " + std::to_string(kMaxSeeds))
      ->check(CLI::Validator(
          [](std::string& text) {
            const auto range = parseSeedRange(text, kMaxSeeds);
            return range ? std::string() : range.error();
          },
          "A-B", "seeds"))
      ->capture_default_str();
  cli.outputDirectory(trials_cmd, "--out", trials.out,
                      "output directory (created; runs are reused when made from the same inputs)")
      ->required();
  trials_cmd
      ->add_option("--methods", trials.methods,
                   "comma-separated: full, gt-align, hm-align, no-rec, no-ia, oracle-lc")
      ->delimiter(',')
      ->check(CLI::IsMember(trialMethods()))
      ->capture_default_str();
  cli.real(trials_cmd, "--speed", trials.speed, "replay speed of every run (0: fastest)",
           {0.0, 1000.0})
      ->capture_default_str();
  cli.inputFile(trials_cmd, "--config", trials.config, "station configuration for every run");
  trials_cmd->add_flag("--redo", trials.redo, "run again where a run's metrics.json exists");
  cli.real(trials_cmd, "--label-confusion", trials.label_confusion,
           "simulate the datasets with this label confusion (see simulate)", {0.0, 1.0});

  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  // Options that would do nothing beside the others given: refused rather than ignored.
  if (*ate_cmd && max_time_difference->count() > 0 && ate.format != "tum")
    return cli.refuse("ate", "--max-time-difference applies to --format tum only");
  for (const CLI::Option* gnc_only : {linear_solver, gnc_inner, keep_chains}) {
    if (*pgo_cmd && gnc_only->count() > 0 && pgo.robust != "gnc")
      return cli.refuse("pgo", gnc_only->get_name() + " applies to --robust gnc only");
  }
  if (*pgo_cmd && pgo_seed->count() > 0 && outliers->count() == 0)
    return cli.refuse("pgo", "--seed applies to --outliers only (the seed of the injection)");
  if (*station_cmd && order_hold->count() > 0 && station.order != "time")
    return cli.refuse("station", "--order-hold applies to --order time only");
  if (*robot_cmd && robot.graph.empty() && (robot.dataset.empty() || robot.robot.empty()))
    return cli.refuse("robot", "--dataset and --robot are required (but with --spark --graph)");
  if (*robot_cmd && !move_text.empty())
    robot.move = hydra_multi::apps::parseMove(move_text).value();
  if (*robot_cmd && !robot.spark && robot.connect.empty())
    return cli.refuse("robot", "--connect is required (or --spark with --bind)");
  if (*robot_cmd && robot.spark && robot.bind.empty())
    return cli.refuse("robot", "--spark needs --bind tcp://HOST:PORT");
  if (*robot_cmd && robot.spark && robot.graph.empty() && robot.speed <= 0.0)
    return cli.refuse("robot",
                      "--spark needs --speed above 0 (a PUB has no acknowledgements to pace it)");
  if (*robot_cmd && robot.mission_start_s && robot.speed <= 0.0)
    return cli.refuse("robot", "--mission-start needs --speed above 0 (robot time on the clock)");
  if (*trials_cmd) {
    const auto range = parseSeedRange(seeds, kMaxSeeds);  // checked while parsing
    trials.first_seed = range.value().first;
    trials.last_seed = range.value().second;
    return runTrials(trials);
  }
  if (*info_cmd) return runInfo(info);
  if (*convert_cmd) return runConvert(convert);
  if (*pgo_cmd) return runPgo(pgo);
  if (*ate_cmd) return runAte(ate);
  if (*simulate_cmd) return runSimulate(simulate);
  if (*evaluate_cmd) return runEvaluate(evaluate);
  if (*dataset_graph_cmd) return runDatasetGraph(dataset_graph);
  if (*detect_cmd) return runDetect(detect);
  if (*run_cmd) return runRun(run);
  if (*station_cmd) return runStationCommand(station);
  if (*robot_cmd) return runRobotCommand(robot);
  if (*keygen_cmd) return runKeygen(keygen);
  if (*watch_cmd) return runWatch(watch);
  if (*view_cmd) return runView(view);
  return 0;
}
