// Pose-graph benchmark: for every graph of ../shared/data/pgo, chordal initialization plus a
// chordal-residual solve, with time, iterations, the SE-Sync cost F and its gap to the known
// global optimum f* (data/README.md). Build in Release (`make bench`).
//
//   bench_pgo [DATA_DIR] [--threads N]

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "hydra_multi/optim/chordal_initialization.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/pose_graph_optimizer.h"

using namespace hydra_multi;

namespace {

struct Case {
  const char* file;
  double f_star;  // < 0: unknown
  const char* note;
};

double seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = "../shared/data";
  int threads = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      data = argv[i];
    }
  }
  const std::vector<Case> cases = {
      {"sphere2500.g2o", 1687.01, "certified (SE-Sync)"},
      {"parking-garage.g2o", 1.2626, "certified (SE-Sync)"},
      {"torus3D.g2o", 2.42e4, "literature, unchecked"},
      {"smallGrid3D.g2o", -1, ""},
      {"tinyGrid3D.g2o", -1, ""},
  };
  std::printf("%-20s %6s %6s %9s %9s %6s %14s %12s %9s  %s\n", "graph", "poses", "edges",
              "init [s]", "solve [s]", "iters", "F", "f*", "gap", "f* source");
  for (const Case& c : cases) {
    const std::string path = data + "/pgo/" + c.file;
    auto file = io::readG2o(path);
    if (!file) {
      std::fprintf(stderr, "bench_pgo: %s\n", file.error().c_str());
      return 1;
    }
    const PoseGraph& g = file.value().graph;
    const NodeId anchor = g.poses.begin()->first;
    const auto start = std::chrono::steady_clock::now();
    auto init = chordalInitialization(g, anchor);
    const double init_s = seconds(start);
    if (!init) {
      std::fprintf(stderr, "bench_pgo: %s: %s\n", c.file, init.error().c_str());
      return 1;
    }
    PoseGraphOptimizerOptions options;
    options.residual = ResidualType::kChordal;
    options.num_threads = threads;
    PoseGraphProblem problem(g, init.value(), anchor, options);
    const SolveSummary summary = problem.solve();
    const double F = sesyncCost(g.edges, problem.poses()).value();
    char gap[32] = "-", f_star[32] = "-";
    if (c.f_star > 0) {
      std::snprintf(gap, sizeof gap, "%+.4f%%", 100.0 * (F - c.f_star) / c.f_star);
      std::snprintf(f_star, sizeof f_star, "%.6g", c.f_star);
    }
    std::printf("%-20s %6zu %6zu %9.3f %9.3f %6d %14.6f %12s %9s  %s\n", c.file, g.poses.size(),
                g.edges.size(), init_s, summary.time_s, summary.iterations, F, f_star, gap, c.note);
  }
  return 0;
}
