// Backend benchmark: the frontend (processor and loop-closure detector) over a whole dataset
// without a backend, then backend rounds on the final state, with the time of every stage
// (alignment, graph assembly, GNC, the whole-graph solve, the backend graph, rooms) and the size
// of the deformation graph. Build in Release (`make bench-backend`).
//
//   bench_backend DATASET_DIR [--rounds N] [--config FILE] [--verbose]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "hydra_multi/station/station.h"
#include "hydra_multi/station/station_config.h"

using namespace hydra_multi;

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr,
                 "usage: bench_backend DATASET_DIR [--rounds N] [--config FILE] [--verbose]\n");
    return 2;
  }
  int rounds = 1;
  StationOptions options;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) {
      rounds = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
      if (Status s = loadStationConfig(argv[++i], options); !s) {
        std::fprintf(stderr, "error: %s\n", s.message().c_str());
        return 1;
      }
    } else if (std::strcmp(argv[i], "--verbose") == 0) {
      options.backend.deformation.solver.progress = [](const std::string& line) {
        std::fprintf(stderr, "  %s\n", line.c_str());
      };
    } else {
      std::fprintf(stderr, "error: unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  auto streams = loadDatasetStreams(argv[1]);
  if (!streams) {
    std::fprintf(stderr, "error: %s\n", streams.error().c_str());
    return 1;
  }
  const auto t0 = std::chrono::steady_clock::now();
  SceneGraphProcessor processor;
  LoopClosureDetector detector;
  for (const RobotUpdate& update : streams.value().updates) {
    const UpdateReport report = processor.process(update);
    if (report.outcome == UpdateOutcome::kApplied) detector.update(processor, report.new_keyframes);
  }
  detector.flush(processor);
  const double frontend_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::vector<PoseGraphEdge> inter = interRobotEdges(detector.loopClosures());
  std::vector<BackendRobot> robots;
  for (const RobotId r : processor.robots()) {
    const RobotFrontendState* state = processor.robot(r);
    robots.push_back(
        {r, &state->pose_graph, &state->control_points, &state->control_point_edges, &state->mesh});
  }
  std::printf("%s: %zu updates, frontend %.1f s, %zu inter-robot loop closures\n", argv[1],
              streams.value().updates.size(), frontend_s, inter.size());
  std::printf("round  aligned  poses  factors  nodes  kept/lc  merges  align_s  build_s    gnc_s  "
              "whole_s  graph_s  rooms_s  total_s\n");
  Backend backend(options.backend);
  const RobotId root =
      *std::min_element(streams.value().robots.begin(), streams.value().robots.end());
  for (int i = 0; i < rounds; ++i) {
    const BackendRoundReport r = backend.round(processor.graph(), robots, inter, root);
    std::printf("%5d  %3zu/%-3zu  %5zu  %7zu  %5zu  %3zu/%-3zu  %3zu/%-3zu  %7.2f  %7.2f  %7.2f  "
                "%7.2f  %7.2f  %7.2f  %7.2f\n",
                i, r.robots_aligned, r.robots, r.variables, r.factors, r.nodes,
                r.inter_robot_inliers, r.inter_robot_loop_closures, r.merges_accepted,
                r.merges_proposed, r.alignment_s, r.build_s, r.gnc_s, r.whole_graph_s, r.graph_s,
                r.rooms_s, r.time_s);
  }
  return 0;
}
