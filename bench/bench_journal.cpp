// Journal benchmark: the station's durable journal (store/journal.h) appending a recorded
// dataset's updates, one transaction each as the station does before every acknowledgement, with
// SQLite's synchronous=FULL and =NORMAL (WAL mode), in a folder of the dataset's file system.
// Prints updates per second and MB per second for each. Build in Release (`make bench-journal`).
//
//   bench_journal DATASET_DIR [WORK_DIR]

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/dataset_files.h"
#include "hydra_multi/store/journal.h"

using namespace hydra_multi;

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_journal DATASET_DIR [WORK_DIR]\n");
    return 2;
  }
  auto manifest = io::readDatasetManifest(argv[1]);
  if (!manifest) {
    std::fprintf(stderr, "bench_journal: %s\n", manifest.error().c_str());
    return 1;
  }
  std::vector<store::JournalEntry> entries;
  size_t bytes = 0;
  for (const io::DatasetRobot& robot : manifest.value().robots) {
    auto records = io::loadRobotStream(robot.stream, robot.robot);
    if (!records) {
      std::fprintf(stderr, "bench_journal: %s\n", records.error().c_str());
      return 1;
    }
    for (const RobotUpdate& u : records.value().updates) {
      entries.push_back({u.robot, 1, u.sequence, io::encodeRobotUpdateBinary(u), u.time_ns});
      bytes += entries.back().payload.size();
    }
  }
  const fs::path work = argc > 2 ? fs::path(argv[2]) : fs::path(argv[1]) / "bench-journal";
  fs::create_directories(work);
  std::printf("%zu updates of %s, %.1f MB, one transaction each, in %s\n", entries.size(), argv[1],
              double(bytes) / (1 << 20), work.c_str());
  for (const auto& [name, durability] : {std::pair{"FULL", store::Durability::kFull},
                                         std::pair{"NORMAL", store::Durability::kNormal}}) {
    const fs::path path = work / (std::string("journal-") + name + ".sqlite");
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(path.string() + suffix);
    auto journal = store::Journal::open(path.string(), durability);
    if (!journal) {
      std::fprintf(stderr, "bench_journal: %s\n", journal.error().c_str());
      return 1;
    }
    const auto start = std::chrono::steady_clock::now();
    for (const store::JournalEntry& e : entries) {
      if (Status s = journal.value()->append(e); !s) {
        std::fprintf(stderr, "bench_journal: %s\n", s.message().c_str());
        return 1;
      }
    }
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("  synchronous=%-6s %8.0f updates/s  %7.1f MB/s  (%.2f s, %.2f ms per update)\n",
                name, entries.size() / s, double(bytes) / (1 << 20) / s, s,
                1e3 * s / entries.size());
  }
  fs::remove_all(work);
  return 0;
}
