#include "hydra_multi/apps/stop_signals.h"

#include <atomic>
#include <csignal>

namespace hydra_multi::apps {
namespace {

std::atomic<bool> stop_requested{false};

extern "C" void onStopSignal(int) { stop_requested = true; }

}  // namespace

StopSignals::StopSignals() {
  stop_requested = false;
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
}

StopSignals::~StopSignals() {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

bool StopSignals::requested() { return stop_requested.load(); }

}  // namespace hydra_multi::apps
