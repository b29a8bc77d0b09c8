// Backend benchmark: the frontend (processor and loop-closure detector) over a whole dataset
// without a backend, then backend rounds on the final state, with the time of every stage
// (alignment, graph assembly, GNC, the whole-graph solve, the backend graph, rooms), the robots
// new or re-aligned since the last round (afresh), the size of the deformation graph, the robust
// factors taken as decided from the last round and those decided again, the pose-graph
// solves, the poses the whole-graph solve moved (moved), whether that solve took the analysis
// made ahead while GNC ran (ahead: 1) and the mesh vertices deformed anew (meshed; the others
// kept from the last round, MeshBinding). With --every K, a round also runs
// after every K updates, as an online station whose backend keeps up would run them. With
// --rounds-of TIMING_CSV, a round runs after the updates each backend round of a station run
// followed (the `timing.csv` of `hydra-multi run`, its rounds while mapping): the station's rounds
// replayed on one thread, each with its own figures. Build in Release (`make bench-backend`).
//
// With --from-scratch, the rounds on the final state take nothing from earlier rounds (as the
// station's last round). With --compare-full, a second backend that solves the whole deformation
// graph every round (DeformationGraphOptions::local_whole_graph off) runs the same rounds, and each
// round prints how far the two backend graphs' nodes are apart (median, max). Where the dataset
// has its ground truth, each round also counts the inter-robot loop closures it kept that the
// truth calls wrong (lc_wrong), the merges it kept that join two true rooms (merges_x) and the
// ATE of its backend graph's keyframes (ate_m); evaluation only, as `run` scores them. Of the
// assembly (build_s), lcsol_s is the loop closures' solve and cand_s the merge candidates. Of the
// round's three solves (in lcsol_s, gnc_s and whole_s), lm_s is the time in Levenberg-Marquardt,
// of it fact_s in the sparse Cholesky factorizations, and anal_s the analyses of the problems'
// patterns (orderings, symbolic factorizations) on the solving thread, one made ahead on the other
// thread not counted; lm_it counts those solves' Levenberg-Marquardt iterations; freed_mb is the
// freed memory the allocator held after the round and back 1 where that was over the budget
// (memory.keep_freed_mb) and handed back to the system (station/freed_memory.h). After
// the online rounds a line sums them up: rounds scored, those with an ATE over 1 m (a robot
// placed in the wrong room or wing) and those keeping wrong loop closures, the median and max ATE.
//
//   bench_backend DATASET_DIR [--rounds N] [--every K | --rounds-of TIMING_CSV] [--config FILE]
//                 [--verbose] [--from-scratch] [--compare-full]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "hydra_multi/core/result.h"
#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/eval/dataset_ground_truth.h"
#include "hydra_multi/station/freed_memory.h"
#include "hydra_multi/station/station.h"
#include "hydra_multi/station/station_config.h"

using namespace hydra_multi;

namespace {

// The updates applied before each round a station run made while mapping: `robot_time_s` of the
// `timing.csv` rows of kind backend with from_scratch 0.
Result<std::set<size_t>> roundsOf(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{"cannot read " + path};
  const auto cellsOf = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream split(line);
    for (std::string cell; std::getline(split, cell, ',');) cells.push_back(cell);
    return cells;
  };
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = cellsOf(line);
  const auto column = [&header](const char* name) {
    return size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const size_t kind = column("kind"), after = column("robot_time_s"),
               scratch = column("from_scratch");
  if (std::max({kind, after, scratch}) >= header.size())
    return Error{path +
                 ": not a station timing.csv (no kind, robot_time_s or from_scratch column)"};
  std::set<size_t> rounds;
  for (size_t row = 2; std::getline(in, line); ++row) {
    std::vector<std::string> cells = cellsOf(line);
    cells.resize(header.size());
    if (cells[kind] != "backend" || cells[scratch] != "0") continue;
    char* end = nullptr;
    const double updates = std::strtod(cells[after].c_str(), &end);
    if (end == cells[after].c_str() || *end != '\0' || !(updates >= 0.0) ||
        updates != double(size_t(updates)))
      return Error{path + ":" + std::to_string(row) + ": robot_time_s '" + cells[after] +
                   "' is not a count of updates"};
    rounds.insert(size_t(updates));
  }
  if (rounds.empty()) return Error{path + ": no backend round while mapping"};
  return rounds;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr,
                 "usage: bench_backend DATASET_DIR [--rounds N] [--every K | --rounds-of "
                 "TIMING_CSV] [--config FILE] [--verbose] [--from-scratch] [--compare-full]\n");
    return 2;
  }
  int rounds = 1;
  size_t every = 0;
  const char* rounds_of = nullptr;  // a station's timing.csv
  StationOptions options;
  bool compare_full = false, from_scratch = false;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) {
      rounds = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--every") == 0 && i + 1 < argc) {
      every = static_cast<size_t>(std::max(1, std::atoi(argv[++i])));
    } else if (std::strcmp(argv[i], "--rounds-of") == 0 && i + 1 < argc) {
      rounds_of = argv[++i];
    } else if (std::strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
      if (Status s = loadStationConfig(argv[++i], options); !s) {
        std::fprintf(stderr, "error: %s\n", s.message().c_str());
        return 1;
      }
    } else if (std::strcmp(argv[i], "--from-scratch") == 0) {
      from_scratch = true;
    } else if (std::strcmp(argv[i], "--compare-full") == 0) {
      compare_full = true;
    } else if (std::strcmp(argv[i], "--verbose") == 0) {
      options.backend.deformation.solver.progress = [](const std::string& line) {
        std::fprintf(stderr, "  %s\n", line.c_str());
      };
    } else {
      std::fprintf(stderr, "error: unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  if (every > 0 && rounds_of != nullptr) {
    std::fprintf(stderr, "error: --every and --rounds-of both say when rounds run; give one\n");
    return 2;
  }
  std::set<size_t> rounds_after;  // --rounds-of: the updates applied before each online round
  if (rounds_of != nullptr) {
    auto read = roundsOf(rounds_of);
    if (!read) {
      std::fprintf(stderr, "error: %s\n", read.error().c_str());
      return 1;
    }
    rounds_after = std::move(read.value());
  }
  const bool online = every > 0 || !rounds_after.empty();
  if (options.keep_freed_mb > 0) keepFreedMemory();
  auto streams = loadDatasetStreams(argv[1]);
  if (!streams) {
    std::fprintf(stderr, "error: %s\n", streams.error().c_str());
    return 1;
  }
  std::optional<DatasetGroundTruth> truth;
  if (auto read = readDatasetGroundTruth(argv[1])) truth = std::move(read.value());
  std::optional<TrueRooms> true_rooms;
  if (truth) true_rooms.emplace(*truth);
  const std::vector<DetectedLoopClosure> kNoLoopClosures;
  const std::vector<AcceptedMerge> kNoMerges;
  const RobotId root =
      *std::min_element(streams.value().robots.begin(), streams.value().robots.end());
  SceneGraphProcessor processor;
  LoopClosureDetector detector;
  Backend backend(options.backend);
  BackendOptions full_options = options.backend;
  full_options.deformation.local_whole_graph = false;
  full_options.deformation.solver.progress = nullptr;
  Backend full(full_options);
  std::vector<BackendRobot> robots;
  long last_wrong = -1;  // of the last round run (-1: no truth)
  double last_ate = -1.0;
  const auto runRound = [&](const std::string& name, bool scratch) {
    robots.clear();
    for (const RobotId r : processor.robots()) {
      const RobotFrontendState* state = processor.robot(r);
      robots.push_back({r, &state->pose_graph, &state->control_points, &state->control_point_edges,
                        &state->mesh});
    }
    // As the station gives them: the alignment's consensus weighs each by its support.
    const std::vector<PoseGraphEdge> inter = interRobotEdges(detector.loopClosures());
    const std::vector<double> support = interRobotSupport(detector.loopClosures());
    const BackendRoundReport r =
        backend.round(processor.graph(), robots, inter, root, support, scratch);
    FreedMemory freed;
    if (options.keep_freed_mb > 0)  // as the station does after a round
      freed = trimFreedMemory(options.keep_freed_mb << 20);
    // Kept inter-robot loop closures the truth calls wrong (-1: no truth).
    long wrong = truth ? 0 : -1;
    const auto stamp = [&processor](NodeId keyframe) -> int64_t {
      const Node* node = processor.graph().findNode(keyframe);
      const AgentAttributes* agent = node ? node->find<AgentAttributes>() : nullptr;
      return agent ? agent->timestamp_ns : -1;
    };
    for (const DetectedLoopClosure& c : truth ? detector.loopClosures() : kNoLoopClosures) {
      const auto kept = backend.loopClosureInliers().find({c.keyframe_a, c.keyframe_b});
      if (!c.interRobot() || kept == backend.loopClosureInliers().end() || !kept->second) continue;
      wrong += !checkLoopClosure(*truth, c.robot_a, stamp(c.keyframe_a), c.robot_b,
                                 stamp(c.keyframe_b), c.T_a_b)
                    .correct;
    }
    // Merges that join two true rooms (-1: no truth).
    long across = truth ? 0 : -1;
    const auto sideOf = [](const AcceptedMerge::Side& s) {
      return MergeSide{s.robot, s.position, s.keyframe_stamp_ns, s.T_robot_keyframe};
    };
    for (const AcceptedMerge& m : true_rooms ? backend.merges() : kNoMerges)
      across += checkMerge(*true_rooms, sideOf(m.target_side), sideOf(m.source_side)).across_rooms;
    // The ATE of the round's backend graph: its keyframes against their true positions (m; -1:
    // no truth or fewer than 3 keyframes matched).
    double ate = -1.0;
    if (truth) {
      if (const auto error = keyframeTrajectoryError(backend.graph(), *truth); error)
        ate = error.value().statistics.rmse;
    }
    std::string apart;
    if (compare_full) {
      full.round(processor.graph(), robots, inter, root, support, scratch);
      std::vector<double> d;
      for (const auto& [id, node] : backend.graph().nodes()) {
        if (const Node* other = full.graph().findNode(id); other != nullptr)
          d.push_back((node.position - other->position).norm());
      }
      std::sort(d.begin(), d.end());
      char text[96];
      std::snprintf(text, sizeof(text), "  apart from the full solve: median %.4f m, max %.4f m",
                    d.empty() ? 0.0 : d[d.size() / 2], d.empty() ? 0.0 : d.back());
      apart = text;
    }
    std::printf(
        "%7s  %3zu/%-3zu  %6zu  %5zu  %7zu  %5zu  %4zu/%-4zu  %4zu/%-4zu  %5zu/%-3zu  %5zu  %6d  "
        "%7.2f  "
        "%7.2f  %7.2f  %7.2f  %7.2f  %7.2f  %7.2f  %6zu  %5d  %7zu  %8ld  %8ld  %7.4f  %7.2f  "
        "%7.2f  %7.2f  %7.2f  %7.2f  %5d  %8.0f  %4d%s\n",
        name.c_str(), r.robots_aligned, r.robots, r.robots_afresh, r.variables, r.factors, r.nodes,
        r.inter_robot_inliers, r.inter_robot_loop_closures, r.merges_accepted, r.merges_proposed,
        r.verdicts_known, r.verdicts_redecided, r.merges_admitted, r.solves, r.alignment_s,
        r.build_s, r.gnc_s, r.whole_graph_s, r.graph_s, r.rooms_s, r.time_s, r.whole_graph_free,
        r.whole_graph_ahead ? 1 : 0, r.vertices_blended, wrong, across, ate, r.loop_closure_solve_s,
        r.candidates_s, r.solver_time.solve_s, r.solver_time.factorization_s,
        r.solver_time.analysis_s, r.solver_time.iterations, freed.bytes / double(1 << 20),
        freed.handed_back ? 1 : 0, apart.c_str());
    std::fflush(stdout);
    last_wrong = wrong;
    last_ate = ate;
    return r.time_s;
  };
  const char* header =
      "  round  aligned  afresh  poses  factors  nodes  kept/lc    merges     known/redo  admit  "
      "solves  "
      "align_s  build_s    gnc_s  whole_s  graph_s  rooms_s  total_s   moved  ahead   meshed  "
      "lc_wrong  "
      "merges_x   "
      " ate_m  lcsol_s   cand_s     lm_s   fact_s   anal_s  lm_it  freed_mb  back\n";
  if (online) std::printf("%s", header);
  const auto t0 = std::chrono::steady_clock::now();
  double online_s = 0.0;
  size_t applied = 0, online_rounds = 0;
  // The online maps against the truth: rounds scored, with an ATE over kWrongMapM, with wrong
  // loop closures kept.
  constexpr double kWrongMapM = 1.0;
  std::vector<double> online_ate;
  size_t wrong_maps = 0, wrong_kept = 0;
  std::string last_wrong_map;
  for (const RobotUpdate& update : streams.value().updates) {
    const UpdateReport report = processor.process(update);
    if (report.outcome != UpdateOutcome::kApplied) continue;
    detector.update(processor, report.new_keyframes);
    ++applied;
    if (every > 0 ? applied % every == 0 : rounds_after.count(applied) != 0) {
      const std::string name = "u" + std::to_string(applied);
      online_s += runRound(name, false);
      ++online_rounds;
      wrong_kept += last_wrong > 0;
      if (last_ate >= 0.0) {
        online_ate.push_back(last_ate);
        if (last_ate > kWrongMapM) {
          ++wrong_maps;
          last_wrong_map = name;
        }
      }
    }
  }
  detector.flush(processor);
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %zu updates, frontend %.1f s, %zu inter-robot loop closures\n", argv[1],
              streams.value().updates.size(), total_s - online_s,
              interRobotEdges(detector.loopClosures()).size());
  if (online_rounds > 0)
    std::printf("online: %zu rounds, %.1f s, %.2f s per round\n", online_rounds, online_s,
                online_s / double(online_rounds));
  if (!online_ate.empty()) {
    std::sort(online_ate.begin(), online_ate.end());
    std::printf(
        "online maps: %zu rounds scored, %zu with an ATE over %.0f m%s%s%s, %zu keeping wrong loop "
        "closures; ATE median %.3f m, max %.3f m\n",
        online_ate.size(), wrong_maps, kWrongMapM, wrong_maps > 0 ? " (the last " : "",
        last_wrong_map.c_str(), wrong_maps > 0 ? ")" : "", wrong_kept,
        online_ate[online_ate.size() / 2], online_ate.back());
  }
  std::printf("%s", header);
  for (int i = 0; i < rounds; ++i) runRound(std::to_string(i), from_scratch);
  return 0;
}
