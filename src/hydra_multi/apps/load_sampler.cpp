#include "hydra_multi/apps/load_sampler.h"

#include <sys/resource.h>
#include <unistd.h>

#include <iomanip>

namespace hydra_multi::apps {

double residentMemoryMb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  if (!(statm >> pages >> resident)) return 0.0;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

Result<std::unique_ptr<LoadSampler>> LoadSampler::start(const std::string& path,
                                                        std::function<size_t()> queued,
                                                        std::chrono::milliseconds period) {
  auto sampler = std::make_unique<LoadSampler>(std::move(queued), period);
  sampler->csv_.open(path, std::ios::trunc);
  if (!sampler->csv_) return Error{"cannot write " + path};
  sampler->csv_ << "wall_s,queued,rss_mb,cpu_user_s,cpu_system_s\n" << std::fixed;
  LoadSampler* s = sampler.get();
  s->thread_ = std::thread([s] {
    std::unique_lock<std::mutex> lock(s->mutex_);
    for (;;) {
      s->sample();
      if (s->wake_.wait_for(lock, s->period_, [s] { return s->stopping_; })) break;
    }
    s->sample();
  });
  return sampler;
}

LoadSampler::LoadSampler(std::function<size_t()> queued, std::chrono::milliseconds period)
    : queued_(std::move(queued)), period_(period) {}

LoadSampler::~LoadSampler() { stop(); }

void LoadSampler::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (csv_.is_open()) csv_.close();
}

void LoadSampler::sample() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return double(t.tv_sec) + double(t.tv_usec) * 1e-6; };
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  csv_ << std::setprecision(3) << wall << "," << queued_() << "," << std::setprecision(1)
       << residentMemoryMb() << "," << std::setprecision(3) << seconds(usage.ru_utime) << ","
       << seconds(usage.ru_stime) << "\n"
       << std::flush;
}

}  // namespace hydra_multi::apps
