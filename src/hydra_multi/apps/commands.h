#pragma once
// The subcommands of `hydra-multi`. Each takes a plain options struct that main() fills from the
// command line, prints to stdout (results) and stderr (errors, progress), and returns the exit
// code: 0 success, 1 failure.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"

namespace hydra_multi::apps {

struct InfoOptions {
  std::string path;
  bool json = false;  ///< exactly one JSON object on stdout
};
int runInfo(const InfoOptions& options);

struct ConvertOptions {
  std::string input;
  std::string output;
};
int runConvert(const ConvertOptions& options);

struct PgoOptions {
  std::vector<std::string> inputs;
  bool unknown_frames = false;        ///< each input file is a robot with an unknown frame
  std::string residual = "geodesic";  ///< geodesic | chordal
  std::string init = "chordal";       ///< odometry | chordal
  std::string robust = "none";        ///< none | gnc
  double outliers = 0.0;              ///< share of injected outliers among all loop closures
  uint64_t seed = 0;
  std::string inliers_xml;   ///< labels: 1-based edge numbers of the inlier loop closures
  std::string inlier_edges;  ///< labels: a g2o file whose edges are the true loop closures
  size_t min_inliers = 5;    ///< k: inliers a robot pair needs to be aligned
  std::string linear_solver = "auto";  ///< auto | cholesky | cg (for the GNC solves)
  int gnc_inner_iterations = 3;        ///< LM iterations per GNC solve (0: up to 100)
  bool keep_chains = false;  ///< GNC over every pose, chains not reduced (RobustPgoOptions)
  std::string groundtruth;   ///< g2o/TORO file with the true poses (or edges to chain)
  std::string output;        ///< optimized graph as g2o
  bool json = false;
  bool skip_bad_lines = false;
  double tolerance = 1e-4;  ///< relative cost change that ends a solve
  int threads = 1;
  bool quiet = false;  ///< no progress lines on stderr
};
int runPgo(const PgoOptions& options);

struct AteOptions {
  std::string estimate;
  std::string reference;
  std::string format = "kitti";       ///< kitti | tum
  double max_time_difference = 0.01;  ///< TUM association (s)
  bool json = false;
};
int runAte(const AteOptions& options);

struct SimulateOptions {
  std::string preset = "office-3";
  uint64_t seed = 1;
  std::string out;
  std::optional<int> robots;  ///< the preset's team size when absent
  double scale = 1.0;
  /// Each robot's chance of labelling an object as its look-alike class (the preset's 0.1 when
  /// absent; 0 as with ground-truth segmentation, like the paper's uHumans2).
  std::optional<double> label_confusion;
  /// Every this many updates a robot sends its whole map as a snapshot (0: only the first).
  size_t snapshot_every = 0;
  /// Robots send no keypoints, no loop closures of their own: only what Hydra robots send.
  bool no_keypoints = false, no_own_loop_closures = false;
  bool quiet = false;  ///< no progress lines on stderr
};
int runSimulate(const SimulateOptions& options);
/// What `simulate` with these options makes (sim/dataset_recipe.h), without making it.
Result<std::string> simulateRecipe(const SimulateOptions& options);

struct EvaluateOptions {
  std::string dataset;
  std::string result;  ///< a scene graph in the global frame (robot 0's)
  bool json = false;
  std::string objects_csv;    ///< when set: every estimated object's verdict, one row each
  std::string keyframes_csv;  ///< when set: every keyframe's position and true position
};
int runEvaluate(const EvaluateOptions& options);

struct DatasetGraphOptions {
  std::string dataset;
  std::string robot;  ///< letter (a, b, ...) or index (0, 1, ...)
  std::string out;
};
int runDatasetGraph(const DatasetGraphOptions& options);

struct DetectOptions {
  std::string dataset;
  bool json = false;
  bool quiet = false;             ///< no progress lines on stderr
  std::string loop_closures_csv;  ///< every detected loop closure, checked against the truth
};
int runDetect(const DetectOptions& options);

struct RunOptions {
  std::string dataset;
  std::string out;
  double speed = 0.0;             ///< 1 real time, 10 faster, 0 as fast as possible
  std::string ablation = "full";  ///< full | no-ia | no-rec
  std::string baseline;           ///< "" | gt-align | hm-align | oracle-lc (evaluation only)
  std::string config;             ///< station configuration file (JSON)
  bool quiet = false;
  bool print_summary = true;  ///< the summary on stdout
  bool bandwidth = true;      ///< write bandwidth.csv and bandwidth.svg (trials leave them out)
  bool viewer = true;         ///< write OUT/viewer/ for `view` (trials leave it out)
  std::string http;           ///< serve the viewer live on HOST:PORT (empty: no server)
};
int runRun(const RunOptions& options);
/// A run's OUT/inputs.json: the method, the configuration (canonical) and the recipe of the
/// dataset (sim/dataset_recipe.h; "null" when it has none) it was made from.
std::string runInputs(const std::string& dataset_recipe, const std::string& method,
                      const std::string& config);

struct TrialsOptions {
  std::string preset = "office-3";
  uint64_t first_seed = 1, last_seed = 5;
  std::string out;
  std::vector<std::string> methods = {"full", "gt-align", "hm-align", "no-rec", "no-ia"};
  double speed = 0.0;
  bool redo = false;  ///< run again where a run's metrics.json exists
  std::string config;
  std::optional<double> label_confusion;  ///< simulate's --label-confusion for the datasets
};
int runTrials(const TrialsOptions& options);
/// The methods `trials` knows: full, the ablations and the baselines of `run`.
const std::vector<std::string>& trialMethods();

struct StationCommandOptions {
  std::string listen = "tcp://127.0.0.1:7800";  ///< ZeroMQ endpoint robots connect to
  std::string out;                              ///< output directory (created)
  std::string config;                           ///< station configuration file (JSON)
  size_t expect_robots = 0;  ///< end once this many robots said BYE (0: at SIGINT/SIGTERM)
  double max_message_mb = 64.0;
  double rate_limit = 500.0;        ///< messages per second per connection (0: none)
  double rate_limit_mb = 0.0;       ///< MB per second per connection (0: none)
  double handshake_s = 10.0;        ///< a connection's ZeroMQ handshake must end within this
  std::string durability = "full";  ///< full | normal: the journal's SQLite synchronous setting
  std::string keys;  ///< folder of the robots' public keys (a.pub, ...); empty: no authentication
  std::string key;   ///< the station's secret key (with `keys`)
  std::string order = "arrival";  ///< arrival | time: the order the frontend takes updates in
  std::string publish;        ///< the fused graph's snapshot service (clone pattern); empty: none
  std::string http;           ///< serve the viewer live on HOST:PORT (empty: no server)
  double order_hold_s = 5.0;  ///< with order time: the longest an update is held
  bool quiet = false;
  std::string spark_publish;   ///< the fused graph in Spark-DSG's wire form on a PUB (empty: none)
  bool spark_no_mesh = false;  ///< with spark_publish: leave the mesh out
  /// Hydra robots, NAME=tcp://HOST:PORT each: a SUB connects to the robot's ZmqSink and its
  /// whole graphs become robot NAME's updates (net/hydra_robots.h).
  std::vector<std::string> spark_robots;
  /// A Hydra robot that sent a graph and then nothing for this long is done, as a BYE (0: never).
  double spark_done_after_s = 0.0;
  /// The Spark-DSG format of the Hydra robots' graphs and of --spark-publish ("1.1.3").
  std::string spark_version = "1.1.3";
};
int runStationCommand(const StationCommandOptions& options);

struct KeygenOptions {
  std::string out;  ///< PREFIX: writes PREFIX.key (secret) and PREFIX.pub (public)
};
int runKeygen(const KeygenOptions& options);

struct RobotCommandOptions {
  std::string dataset;
  std::string robot;    ///< letter (a, b, ...)
  std::string connect;  ///< the station's endpoint
  double speed =
      0.0;  ///< robot time: 1 real time, 10 faster, 0 as fast as the station acknowledges
  double timeout_s = 60.0;  ///< give up when the station has not taken everything by then
  std::string key;          ///< the robot's secret key (CURVE); empty: none
  std::string station_key;  ///< the station's public key (with `key`)
  /// Unix time the first update is due (with speed > 0); updates due before the process started
  /// are folded into the robot's map, not sent. Absent: the process's start.
  std::optional<double> mission_start_s;
  bool full_resend = false;       ///< the whole map every update
  std::string compress = "zstd";  ///< zstd or none
  /// Speak as a Hydra robot instead: bind a PUB at `bind` and publish the robot's whole graph in
  /// Spark-DSG's wire form after every update, as Hydra's ZmqSink does (no station protocol).
  bool spark = false;
  std::string bind;
  /// With spark: publish this graph file (any format `info` reads) every `every_s` seconds, as a
  /// Hydra robot whose map no longer changes, `count` times (0: until SIGINT or SIGTERM).
  std::string graph;
  double every_s = 1.0;
  size_t count = 0;
  /// With spark: the graph as a robot whose odometric frame is turned by `move_yaw_deg` about z
  /// and offset by `move_offset` would have mapped it ("X,Y,Z,YAW_DEG" on the command line).
  std::optional<std::array<double, 4>> move;
  std::string spark_version = "1.1.3";  ///< with spark: the Spark-DSG format published
  bool quiet = false;
};
/// Parses "X,Y,Z,YAW_DEG" (metres, degrees); an error says what is wrong.
Result<std::array<double, 4>> parseMove(const std::string& text);
int runRobotCommand(const RobotCommandOptions& options);

struct WatchOptions {
  std::string connect;     ///< a station's --publish endpoint
  std::string out;         ///< the latest graph goes here (any graph format); empty: none
  size_t count = 0;        ///< end after this many fused updates (0: at the station's final one)
  double timeout_s = 0.0;  ///< end after this many seconds (0: no limit)
  /// A Spark-DSG publisher instead (a Hydra robot's ZmqSink, station --spark-publish): a SUB
  /// that takes each whole graph in Spark-DSG's wire form.
  bool spark = false;
  double idle_s =
      0.0;  ///< with spark: end once nothing came for this long after a graph (0: never)
  std::string spark_version = "1.1.3";  ///< with spark: the publisher's Spark-DSG format
  bool quiet = false;
};
int runWatch(const WatchOptions& options);

struct ViewOptions {
  std::string dir;                      ///< a run's or station's output folder
  std::string http = "127.0.0.1:7880";  ///< HOST:PORT (port 0: a free one)
  std::string page;                     ///< the built page's folder (default: beside the binary)
  /// Above 0: the history is played as if live, one view every this many seconds.
  double replay_s = 0.0;
  bool quiet = false;
};
int runView(const ViewOptions& options);

/// Prints "hydra-multi: error: <message>" on stderr and returns 1.
int fail(const std::string& message);

}  // namespace hydra_multi::apps
