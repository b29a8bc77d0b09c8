// `hydra-multi run --dataset DIR --out OUT [--speed X] [--ablation A] [--baseline B]
// [--config FILE]`: the station over a dataset's streams, online (station/station.h), then the
// outputs and, read only after the run, the ground truth's verdict: OUT/graph.json,
// graph.spark.json, mesh.ply, metrics.json, config.json, inputs.json (what the run was made
// from), timing.csv, loop_closures.csv (every inter-robot loop closure with the station's
// verdicts and the truth's).
//
// Ablations (paper Table II): no-ia without initial alignment, no-rec without reconciliation.
// Baselines (paper Table I; evaluation only, never the station's normal mode): gt-align places
// the single-robot graphs (each optimized with its own loop closures) by the true start poses;
// hm-align by our initial alignment, without joint optimization; oracle-lc is the full system fed
// only the inter-robot loop closures the ground truth calls correct.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/loop_closure_csv.h"
#include "hydra_multi/apps/run_viewer.h"
#include "hydra_multi/apps/score_json.h"
#include "hydra_multi/apps/station_outputs.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/eval/trajectory_error.h"
#include "hydra_multi/sim/dataset_recipe.h"
#include "hydra_multi/station/frontend_digest.h"
#include "hydra_multi/station/station.h"
#include "hydra_multi/station/station_config.h"

namespace hydra_multi::apps {

std::string runInputs(const std::string& dataset_recipe, const std::string& method,
                      const std::string& config) {
  nlohmann::ordered_json inputs;
  inputs["method"] = method;
  inputs["config"] = nlohmann::ordered_json::parse(config, nullptr, false);
  inputs["dataset"] = nlohmann::ordered_json::parse(dataset_recipe, nullptr, false);
  return inputs.dump();
}

int runRun(const RunOptions& o) {
  namespace fs = std::filesystem;
  auto streams = loadDatasetStreams(o.dataset);
  if (!streams) return fail(streams.error());
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return fail("cannot create " + o.out + ": " + ec.message());
  StationOptions options;
  options.speed = o.speed;
  if (!o.config.empty()) {
    if (Status s = loadStationConfig(o.config, options); !s) return fail(s.message());
  }
  const auto config = canonicalStationConfig(o.config);
  if (!config) return fail(config.error());
  if (o.ablation == "no-ia") options.backend.initial_alignment = false;
  if (o.ablation == "no-rec") options.backend.reconcile = false;
  // Baselines read the ground truth before the run: they are yardsticks, not the station.
  std::optional<DatasetGroundTruth> oracle;
  if (!o.baseline.empty()) {
    auto truth = readDatasetGroundTruth(o.dataset);
    if (!truth) return fail(truth.error());
    oracle = std::move(truth.value());
  }
  if (o.baseline == "gt-align" || o.baseline == "hm-align") {
    options.backend.joint_optimization = false;
    options.backend.reconcile = false;
  }
  if (o.baseline == "gt-align") {
    const RobotId root = *std::min_element(oracle->robots.begin(), oracle->robots.end());
    const Eigen::Isometry3d T_root_world = oracle->start_poses.at(root).inverse();
    for (const auto& [robot, T_world_start] : oracle->start_poses)
      options.backend.given_alignment[robot] = T_root_world * T_world_start;
  }
  if (o.baseline == "oracle-lc") {
    options.loop_closure_filter = [&oracle](const DetectedLoopClosure& c, const SceneGraph& g) {
      const auto stamp = [&g](NodeId id) -> int64_t {
        const Node* node = g.findNode(id);
        const AgentAttributes* agent = node ? node->find<AgentAttributes>() : nullptr;
        return agent ? agent->timestamp_ns : -1;
      };
      return checkLoopClosure(*oracle, c.robot_a, stamp(c.keyframe_a), c.robot_b,
                              stamp(c.keyframe_b), c.T_a_b)
          .correct;
    };
  }
  if (!o.quiet) options.log = [](const std::string& line) { std::cerr << line << std::endl; };
  for (const std::string& skipped : streams.value().skipped)
    std::cerr << "station: skipped " << skipped << std::endl;
  for (const std::string& warning : streams.value().warnings)
    std::cerr << "station: warning: " << warning << std::endl;
  if (!o.quiet)
    std::cerr << "station: " << streams.value().updates.size() << " updates of "
              << streams.value().robots.size() << " robots, speed "
              << (o.speed > 0 ? std::to_string(o.speed) : std::string("as fast as possible"))
              << ", " << (o.baseline.empty() ? "ablation " + o.ablation : "baseline " + o.baseline)
              << std::endl;
  std::unique_ptr<RunViewer> viewer;
  if (o.viewer || !o.http.empty()) {
    // The replay's links for the viewer's status: a robot's bytes are those of its records up to
    // what the station has applied, and it is done once all are.
    auto sent = std::make_shared<std::map<RobotId, std::map<uint64_t, uint64_t>>>();
    for (const RobotUpdate& u : streams.value().updates)
      (*sent)[u.robot][u.sequence] = io::encodeRobotUpdateBinary(u).size();
    for (auto& [robot, bytes] : *sent) {
      uint64_t total = 0;
      for (auto& [sequence, b] : bytes) b = total += b;  // through this sequence
    }
    const RunViewer::Links links = [sent](const RoundOutput* round) {
      std::map<RobotId, web::RobotLink> out;
      if (round == nullptr) return out;
      for (const auto& [robot, progress] : round->progress) {
        const auto it = sent->find(robot);
        if (it == sent->end() || it->second.empty()) continue;
        const auto through = it->second.lower_bound(progress.next_sequence);
        web::RobotLink& link = out[robot];
        link.bytes = through == it->second.begin() ? 0 : std::prev(through)->second;
        link.done = through == it->second.end();
        link.connected = !link.done;
      }
      return out;
    };
    auto opened = RunViewer::open(o.out, o.http, links, o.quiet);
    if (!opened) return fail(opened.error());
    viewer = std::move(opened).value();
    RunViewer* v = viewer.get();
    options.on_round = [v](const RoundOutput& round) { v->onRound(round); };
    if (!viewer->url().empty())
      std::cerr << "station: the live viewer is at " << viewer->url() << std::endl;
  }
  const StationResult result = runStation(streams.value(), options);
  if (viewer) {
    if (Status s = viewer->finish(result.graph); !s) return fail(s.message());
  }

  const fs::path out(o.out);
  // After a team's mission these steps take a while (20 robots at scale 3: about a minute).
  const auto step = [&o](const std::string& what) {
    if (!o.quiet) std::cerr << "station: " << what << std::endl;
  };
  step("writing the graph, mesh and timing to " + o.out);
  if (Status s = writeStationOutputs(o.out, result); !s) return fail(s.message());
  // What the streams' updates weigh against full resends of each robot's map (bandwidth.h).
  RobotBandwidth sent;
  if (o.bandwidth) {
    step("measuring the updates against full resends of each robot's map");
    BandwidthLedger ledger;
    for (const RobotUpdate& u : streams.value().updates) ledger.add(u);
    auto bandwidth = writeBandwidth(o.out, ledger);
    if (!bandwidth) return fail(bandwidth.error());
    sent = teamBandwidth(bandwidth.value());
  }

  // Evaluation, after the run: only now is the ground truth read.
  step("evaluating against the ground truth");
  auto truth = readDatasetGroundTruth(o.dataset);
  if (!truth) return fail(truth.error());
  const SceneGraphScore score =
      evaluateSceneGraph(result.graph, truth.value(), result.global_robot);
  // Inter-robot loop closures: detected, kept by the alignment's averaging and by GNC, and of
  // each how many the ground truth calls correct.
  size_t inter = 0, inter_correct = 0, inliers = 0, correct_inliers = 0;
  size_t alignment_inliers = 0, alignment_correct = 0;
  std::ofstream closures_csv(out / "loop_closures.csv");
  writeLoopClosureCsvHeader(closures_csv, true);
  for (const DetectedLoopClosure& c : result.loop_closures) {
    if (!c.interRobot()) continue;
    ++inter;
    // Stamps from the frontend: robots not aligned are not in the backend graph.
    const auto stamp = [&](NodeId id) { return keyframeStamp(result, id); };
    const LoopClosureCheck check = checkLoopClosure(truth.value(), c.robot_a, stamp(c.keyframe_a),
                                                    c.robot_b, stamp(c.keyframe_b), c.T_a_b);
    const LoopClosureVerdict verdict = verdictOf(result, c);
    writeLoopClosureCsvRow(closures_csv, c, stamp(c.keyframe_a), stamp(c.keyframe_b), truth.value(),
                           check, verdict);
    inter_correct += check.correct;
    alignment_inliers += verdict.alignment_inlier;
    alignment_correct += verdict.alignment_inlier && check.correct;
    inliers += verdict.kept;
    correct_inliers += verdict.kept && check.correct;
  }
  if (!closures_csv) return fail("cannot write " + (out / "loop_closures.csv").string());
  // Merges of the last round that joined two different true rooms.
  size_t merges_across_rooms = 0;
  const auto sideOf = [](const AcceptedMerge::Side& s) {
    return MergeSide{s.robot, s.position, s.keyframe_stamp_ns, s.T_robot_keyframe};
  };
  const TrueRooms true_rooms(truth.value());
  for (const AcceptedMerge& m : result.merges) {
    const MergeCheck check = checkMerge(true_rooms, sideOf(m.target_side), sideOf(m.source_side));
    if (!check.across_rooms) continue;
    ++merges_across_rooms;
    if (!o.quiet) {
      const auto room = [&truth](int id) {
        const auto& ids = truth.value().room_ids;
        const auto it = std::find(ids.begin(), ids.end(), id);
        const std::string kind =
            it == ids.end() ? "" : " (" + truth.value().room_kinds[it - ids.begin()] + ")";
        return std::to_string(id) + kind;
      };
      std::cerr << "evaluation: merge of " << m.source.str() << " into " << m.target.str() << " ("
                << layerName(m.layer) << ") joins two true rooms, " << room(check.room_b) << " and "
                << room(check.room_a) << ", " << check.true_distance_m << " m apart" << std::endl;
    }
  }
  const StationTimes times = stationTimes(result);
  // Updates: applied (on arrival or from the reorder buffer), refused as invalid, and those behind
  // a missing one (a skipped record) that were never applied: buffered or refused while the robot
  // waited for a snapshot.
  const size_t applied = result.counts.appliedTotal();
  const size_t behind_gap = result.counts.behindGap();
  nlohmann::ordered_json metrics = scoreJson(score);
  const nlohmann::ordered_json extra = {
      {"lc_inter_detected", inter},
      {"lc_inter_inliers", inliers},
      {"lc_inter_precision", inliers ? nlohmann::ordered_json(double(correct_inliers) / inliers)
                                     : nlohmann::ordered_json(nullptr)},
      {"lc_inter_correct", inter_correct},
      {"lc_alignment_inliers", alignment_inliers},
      {"lc_alignment_correct", alignment_correct},
      {"updates_applied", applied},
      {"updates_skipped", streams.value().skipped.size()},
      {"updates_rejected", result.counts.rejected},
      {"updates_behind_gap", behind_gap},
      {"robots", result.robots},
      {"global_frame_robot", result.global_robot.str()},
      {"robots_aligned", result.aligned.size()},
      {"merges_accepted", result.rounds.empty() ? 0 : result.rounds.back().report.merges_accepted},
      {"merges_undone", result.rounds.empty() ? 0 : result.rounds.back().report.merges_undone},
      {"merges_label", result.rounds.empty() ? 0 : result.rounds.back().report.label_merges},
      {"merges_across_rooms", merges_across_rooms},
      {"frontend_ms_p50", times.frontend_ms_p50},
      {"frontend_ms_max", times.frontend_ms_max},
      {"backend_ms_p50", times.backend_ms_p50},
      {"backend_ms_max", times.backend_ms_max},
      {"backend_last_ms", times.backend_last_ms},
      {"backend_rounds", result.rounds.size()},
      {"peak_memory_mb", times.peak_memory_mb},
      {"frontend_digest", digestHex(result.frontend_digest)},
      {"wall_s", result.wall_s},
      {"speed", o.speed},
      {"method", o.baseline.empty() ? o.ablation : o.baseline}};
  metrics.update(extra);
  std::ofstream(out / "metrics.json") << metrics.dump(2) << "\n";
  std::ofstream(out / "config.json") << config.value() << "\n";
  // What the run was made from, so that a later `trials` reuses it only for the same inputs.
  const auto recipe = sim::readDatasetRecipe(o.dataset);
  std::ofstream(out / "inputs.json")
      << runInputs(recipe ? recipe.value() : "null", metrics["method"].get<std::string>(),
                   config.value())
      << "\n";

  const auto show = [](const std::optional<double>& v, int precision) {
    if (!v) return std::string("n/a");
    std::ostringstream s;
    s << std::fixed << std::setprecision(precision) << *v;
    return s.str();
  };
  if (!o.print_summary) return 0;
  std::cout << std::fixed << std::setprecision(2) << "station over " << o.dataset << ": "
            << result.updates.size() << " updates, " << result.rounds.size() << " backend rounds, "
            << result.wall_s << " s\n"
            << "  updates               "
            << describeUpdates(result.counts, streams.value().skipped.size()) << "\n"
            << "  robots aligned        " << result.aligned.size() << " of " << result.robots
            << "; global frame: robot " << result.global_robot.str() << "'s\n"
            << "  inter-robot closures  " << inter << " detected (" << inter_correct
            << " correct), " << alignment_inliers << " inliers of the alignment ("
            << alignment_correct << " correct), " << inliers << " kept by GNC (" << correct_inliers
            << " correct)\n"
            << "  merges (last round)   "
            << (result.rounds.empty() ? 0 : result.rounds.back().report.merges_accepted)
            << " accepted of "
            << (result.rounds.empty() ? 0 : result.rounds.back().report.merges_proposed)
            << " proposed, "
            << (result.rounds.empty() ? 0 : result.rounds.back().report.merges_undone)
            << " undone, " << (result.rounds.empty() ? 0 : result.rounds.back().report.label_merges)
            << " by label votes, " << merges_across_rooms << " across two true rooms\n"
            << "  ATE                   " << show(score.ate_rmse_m, 3) << " m\n"
            << "  objects found         " << show(score.objects_found_pct, 1) << " %\n"
            << "  objects correct       " << show(score.objects_correct_pct, 1) << " % ("
            << score.num_objects << " objects, threshold " << score.object_threshold_m << " m)\n"
            << "    of which            " << score.objects_correct << " correct ("
            << score.objects_duplicates << " duplicates), " << score.objects_wrong_label
            << " wrong label, " << score.objects_misplaced << " misplaced\n"
            << "  places error          " << show(score.places_position_error_m, 3) << " m\n"
            << "  rooms                 " << score.num_rooms << ", precision "
            << show(score.rooms_precision, 2) << ", recall " << show(score.rooms_recall, 2) << "\n"
            << "  frontend per update   median " << times.frontend_ms_p50 << " ms, max "
            << times.frontend_ms_max << " ms\n"
            << "  backend per round     median " << times.backend_ms_p50 / 1e3 << " s, max "
            << times.backend_ms_max / 1e3 << " s; the last, from scratch, "
            << times.backend_last_ms / 1e3 << " s\n"
            << "  peak memory           " << show(times.peak_memory_mb, 0) << " MB\n"
            << "  bandwidth             " << sent.record_bytes
            << " bytes of updates; as full resends " << sent.full_resend_bytes << " bytes, "
            << show(fullResendRatio(sent), 1) << " times more\n"
            << "outputs in " << o.out
            << ": graph.json, graph.spark.json, mesh.ply, metrics.json, config.json, "
               "inputs.json, timing.csv, loop_closures.csv, bandwidth.csv, bandwidth.svg\n";
  return 0;
}

}  // namespace hydra_multi::apps
