// The station's load.csv: a row at the start, once a period, and at the stop, each with the
// queue's length as the station reported it then, resident memory and CPU time.

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "hydra_multi/apps/load_sampler.h"

namespace hydra_multi::apps {
namespace {

TEST(LoadSampler, RowsOfQueueMemoryAndCpu) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("load_sampler_" + std::to_string(getpid()) + ".csv"))
                               .string();
  std::atomic<size_t> calls{0};
  {
    auto sampler = LoadSampler::start(
        path, [&calls] { return calls++ * 10; }, std::chrono::milliseconds(20));
    ASSERT_TRUE(sampler.ok()) << sampler.error();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    sampler.value()->stop();
    sampler.value()->stop();  // again: nothing more
  }
  std::ifstream csv(path);
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "wall_s,queued,rss_mb,cpu_user_s,cpu_system_s");
  size_t rows = 0;
  double last_wall = -1.0;
  while (std::getline(csv, line)) {
    std::stringstream s(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(s, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 5u) << line;
    EXPECT_GE(v[0], last_wall);
    last_wall = v[0];
    EXPECT_EQ(v[1], 10.0 * rows);  // the queue as reported at that sample
    EXPECT_GT(v[2], 0.0);
    EXPECT_GE(v[3], 0.0);
    EXPECT_GE(v[4], 0.0);
    ++rows;
  }
  EXPECT_EQ(rows, calls.load());
  EXPECT_GE(rows, 2u);  // at least the start and the stop
  std::filesystem::remove(path);
  EXPECT_FALSE(
      LoadSampler::start(
          "/nonexistent-folder/load.csv", [] { return size_t{0}; }, std::chrono::milliseconds(20))
          .ok());
}

}  // namespace
}  // namespace hydra_multi::apps
