// Bandwidth benchmark (the paper's Fig. 9b): a recorded dataset's updates as the station counts
// them (station/bandwidth.h): bytes per robot and per category, against a full resend of each
// robot's map at every update; then the same payloads compressed with zstd at a few levels, with
// the time it takes to compress and decompress them. Build in Release (`make bench-bandwidth`).
//
//   bench_bandwidth DATASET_DIR

#include <zstd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/dataset_files.h"
#include "hydra_multi/station/bandwidth.h"

using namespace hydra_multi;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_bandwidth DATASET_DIR\n");
    return 2;
  }
  auto manifest = io::readDatasetManifest(argv[1]);
  if (!manifest) {
    std::fprintf(stderr, "bench_bandwidth: %s\n", manifest.error().c_str());
    return 1;
  }
  BandwidthLedger ledger;
  std::vector<std::string> payloads;
  for (const io::DatasetRobot& robot : manifest.value().robots) {
    auto records = io::loadRobotStream(robot.stream, robot.robot);
    if (!records) {
      std::fprintf(stderr, "bench_bandwidth: %s\n", records.error().c_str());
      return 1;
    }
    for (const RobotUpdate& u : records.value().updates) {
      ledger.add(u);
      payloads.push_back(io::encodeRobotUpdateBinary(u));
    }
  }
  const Clock::time_point start = Clock::now();
  const std::vector<UpdateBandwidth> rows = ledger.rows();
  const double ledger_s = secondsSince(start);
  std::printf(
      "%zu updates of %s; ledger (each robot's map as a full resend at every update) "
      "in %.2f s\n\n",
      rows.size(), argv[1], ledger_s);
  std::printf("%-6s %8s %10s %10s %10s %10s %10s %10s %12s %7s\n", "robot", "updates", "ours MB",
              "graph MB", "mesh MB", "poses MB", "deform MB", "descr MB", "full MB", "ratio");
  struct Sums {
    size_t updates = 0, wire = 0, graph = 0, mesh = 0, poses = 0, deform = 0, descr = 0, full = 0;
  };
  std::map<RobotId, Sums> per_robot;
  Sums team;
  for (const UpdateBandwidth& r : rows) {
    for (Sums* s : {&per_robot[r.robot], &team}) {
      ++s->updates;
      s->wire += r.wire_bytes;
      s->graph += r.parts.nodes_edges;
      s->mesh += r.parts.mesh;
      s->poses += r.parts.pose_graph;
      s->deform += r.parts.deformation;
      s->descr += r.parts.descriptors;
      s->full += r.full_resend_bytes.value_or(0);
    }
  }
  const auto line = [](const std::string& name, const Sums& s) {
    std::printf("%-6s %8zu %10.3f %10.3f %10.3f %10.3f %10.3f %10.3f %12.1f %7.1f\n", name.c_str(),
                s.updates, s.wire / 1e6, s.graph / 1e6, s.mesh / 1e6, s.poses / 1e6, s.deform / 1e6,
                s.descr / 1e6, s.full / 1e6, s.wire ? double(s.full) / double(s.wire) : 0.0);
  };
  for (const auto& [robot, s] : per_robot) line(robot.str(), s);
  line("team", team);

  std::printf("\nzstd on each update's payload (%zu payloads, %.3f MB):\n", payloads.size(),
              team.wire / 1e6);
  std::printf("%6s %12s %8s %14s %16s\n", "level", "MB", "saved", "compress MB/s",
              "decompress MB/s");
  for (const int level : {1, 3, 9, 19}) {
    std::vector<std::string> packed;
    size_t packed_bytes = 0;
    Clock::time_point t = Clock::now();
    for (const std::string& p : payloads) {
      std::string out(ZSTD_compressBound(p.size()), '\0');
      const size_t n = ZSTD_compress(out.data(), out.size(), p.data(), p.size(), level);
      if (ZSTD_isError(n)) {
        std::fprintf(stderr, "bench_bandwidth: zstd: %s\n", ZSTD_getErrorName(n));
        return 1;
      }
      out.resize(n);
      packed_bytes += n;
      packed.push_back(std::move(out));
    }
    const double compress_s = secondsSince(t);
    t = Clock::now();
    for (size_t i = 0; i < packed.size(); ++i) {
      std::string out(payloads[i].size(), '\0');
      const size_t n = ZSTD_decompress(out.data(), out.size(), packed[i].data(), packed[i].size());
      if (ZSTD_isError(n) || out != payloads[i]) {
        std::fprintf(stderr, "bench_bandwidth: zstd did not give back payload %zu\n", i);
        return 1;
      }
    }
    const double decompress_s = secondsSince(t);
    std::printf("%6d %12.3f %7.1f%% %14.0f %16.0f\n", level, packed_bytes / 1e6,
                100.0 * (1.0 - double(packed_bytes) / double(team.wire)),
                team.wire / 1e6 / compress_s, team.wire / 1e6 / decompress_s);
  }
  return 0;
}
