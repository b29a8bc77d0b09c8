#pragma once
// The station's load over time: a thread that, once a period, appends to a CSV the seconds since
// it started, the updates waiting on the station's ingest queue (Station::queued), the process's
// resident memory (MB) and its CPU time (user and system, s). Stopped (and the file closed) by
// stop() or the destructor; a row is written at the start and at the stop.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "hydra_multi/core/result.h"

namespace hydra_multi::apps {

class LoadSampler {
 public:
  /// Opens `path` (written anew) and starts sampling `queued` every `period`.
  static Result<std::unique_ptr<LoadSampler>> start(const std::string& path,
                                                    std::function<size_t()> queued,
                                                    std::chrono::milliseconds period);
  ~LoadSampler();
  void stop();

  LoadSampler(std::function<size_t()> queued, std::chrono::milliseconds period);

 private:
  void sample();

  std::function<size_t()> queued_;
  std::chrono::milliseconds period_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::ofstream csv_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

/// The process's resident memory now (MB; 0 where /proc/self/statm cannot be read).
double residentMemoryMb();

}  // namespace hydra_multi::apps
