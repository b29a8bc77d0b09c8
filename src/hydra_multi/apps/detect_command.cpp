// `hydra-multi detect --dataset DIR [--json]`: the station's frontend alone (no backend) over a
// dataset's streams, online: every update goes through the scene-graph processor and the
// loop-closure detector in arrival order, timed. Afterwards, and only then, the evaluation code
// checks the loop closures against the ground truth (within 1 m and 10 degrees); with
// --loop-closures FILE every one of them is written to a CSV file with its error.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/loop_closure_csv.h"
#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/eval/trajectory_error.h"
#include "hydra_multi/frontend/loop_closure_detector.h"
#include "hydra_multi/station/dataset_replay.h"

namespace hydra_multi::apps {
namespace {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t i = static_cast<size_t>(std::ceil(p * double(values.size()))) - (p > 0 ? 1 : 0);
  return values[std::min(i, values.size() - 1)];
}

}  // namespace

int runDetect(const DetectOptions& o) {
  const auto progress = [&](const std::string& line) {
    if (!o.quiet) std::cerr << line << std::endl;
  };
  auto streams = loadDatasetStreams(o.dataset);
  if (!streams) return fail(streams.error());
  const DatasetStreams& input = streams.value();
  for (const std::string& skipped : input.skipped) std::cerr << "skipped " << skipped << std::endl;
  for (const std::string& warning : input.warnings)
    std::cerr << "warning: " << warning << std::endl;
  progress("replaying " + std::to_string(input.updates.size()) + " updates of " +
           std::to_string(input.robots.size()) + " robots");

  SceneGraphProcessor processor({}, [&](const std::string& line) { progress("warning: " + line); });
  LoopClosureDetector detector;
  std::vector<double> frontend_ms;
  for (size_t i = 0; i < input.updates.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    const UpdateReport report = processor.process(input.updates[i]);
    if (report.outcome == UpdateOutcome::kApplied) detector.update(processor, report.new_keyframes);
    frontend_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    if ((i + 1) % 100 == 0 || i + 1 == input.updates.size()) {
      progress("  " + std::to_string(i + 1) + "/" + std::to_string(input.updates.size()) +
               " updates, " + std::to_string(processor.graph().numNodes()) + " nodes, " +
               std::to_string(detector.loopClosures().size()) + " loop closures");
    }
  }
  detector.flush(processor);  // the last keyframes of every robot, at the end of the replay
  // A robot whose stream did not all arrive: what the frontend has of it (as `run` says it).
  for (const RobotId robot : input.robots) {
    const auto damaged = input.skipped_per_robot.find(robot);
    const size_t skipped = damaged == input.skipped_per_robot.end() ? 0 : damaged->second;
    if (!streamIsWhole(processor.order(robot), skipped))
      std::cerr << describeStream(robot, processor.order(robot), skipped) << std::endl;
  }

  // Evaluation, after the detector has finished: only now is the ground truth read.
  auto truth = readDatasetGroundTruth(o.dataset);
  if (!truth) return fail(truth.error());
  const SceneGraph& graph = processor.graph();
  size_t inter = 0, inter_correct = 0, intra = 0, intra_correct = 0;
  std::map<std::string, size_t> by_layer = {{"objects", 0}, {"visual", 0}};
  std::map<std::string, size_t> correct_by_layer = {{"objects", 0}, {"visual", 0}};
  std::map<std::pair<RobotId, RobotId>, std::pair<size_t, size_t>> by_pair;
  std::ofstream csv;
  if (!o.loop_closures_csv.empty()) {
    csv.open(o.loop_closures_csv);
    if (!csv) return fail("cannot write " + o.loop_closures_csv);
    writeLoopClosureCsvHeader(csv, false);
  }
  for (const DetectedLoopClosure& c : detector.loopClosures()) {
    const auto stamp = [&](NodeId id) {
      return graph.getNode(id).find<AgentAttributes>()->timestamp_ns;
    };
    const LoopClosureCheck check = checkLoopClosure(truth.value(), c.robot_a, stamp(c.keyframe_a),
                                                    c.robot_b, stamp(c.keyframe_b), c.T_a_b);
    if (csv.is_open())
      writeLoopClosureCsvRow(csv, c, stamp(c.keyframe_a), stamp(c.keyframe_b), truth.value(),
                             check);
    if (c.interRobot()) {
      ++inter;
      inter_correct += check.correct;
      ++by_layer[loopClosureSourceName(c.source)];
      correct_by_layer[loopClosureSourceName(c.source)] += check.correct;
      auto& pair = by_pair[std::minmax(c.robot_a, c.robot_b)];
      ++pair.first;
      pair.second += check.correct;
    } else {
      ++intra;
      intra_correct += check.correct;
    }
  }
  const double p50 = percentile(frontend_ms, 0.5), p95 = percentile(frontend_ms, 0.95);
  const double max =
      frontend_ms.empty() ? 0.0 : *std::max_element(frontend_ms.begin(), frontend_ms.end());
  const UpdateCounts counts = processor.counts();
  if (o.json) {
    const nlohmann::ordered_json j = {
        {"updates", input.updates.size()},
        {"updates_skipped", input.skipped.size()},
        {"updates_applied", counts.appliedTotal()},
        {"updates_rejected", counts.rejected},
        {"updates_behind_gap", counts.behindGap()},
        {"nodes", graph.numNodes()},
        {"inter_lc_detected", inter},
        {"inter_lc_correct", inter_correct},
        {"inter_lc_by_layer", {{"objects", by_layer["objects"]}, {"visual", by_layer["visual"]}}},
        {"intra_lc", intra},
        {"frontend_ms_p50", p50},
        {"frontend_ms_p95", p95},
        {"frontend_ms_max", max}};
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::cout << std::fixed << std::setprecision(2) << "frontend over " << o.dataset << ": "
            << input.updates.size() << " updates, " << graph.numNodes() << " nodes, "
            << detector.keyframesDescribed() << " keyframes described\n"
            << "updates: " << describeUpdates(counts, input.skipped.size()) << " ("
            << counts.duplicates << " duplicates, " << counts.applied_from_buffer
            << " applied from the reorder buffer)\n"
            << "inter-robot loop closures: " << inter << " detected, " << inter_correct
            << " correct (within 1 m and 10 degrees of the truth)\n";
  for (const auto& [pair, counts] : by_pair) {
    std::cout << "  robots " << pair.first.str() << "-" << pair.second.str() << ": " << counts.first
              << " detected, " << counts.second << " correct\n";
  }
  for (const auto& [layer, n] : by_layer) {
    std::cout << "  verified by " << layer << ": " << n << " (" << correct_by_layer[layer]
              << " correct)\n";
  }
  std::cout << "intra-robot loop closures: " << intra << " detected, " << intra_correct
            << " correct\n"
            << "frontend time per update: median " << p50 << " ms, 95th percentile " << p95
            << " ms, max " << max << " ms\n";
  return 0;
}

}  // namespace hydra_multi::apps
