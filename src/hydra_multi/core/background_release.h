#pragma once
// BackgroundRelease: objects handed over (keep) are destroyed on a second thread, at the lowest
// priority (startInBackground, background_task.h), when release() is called, instead of where
// their owner is done with them: freeing a large tree of maps costs its owner nothing. One
// release runs at a time: release() and the destructor wait for the one before. Not thread-safe:
// keep and release from one thread.

#include <future>
#include <memory>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "hydra_multi/core/background_task.h"

namespace hydra_multi {

class BackgroundRelease {
 public:
  BackgroundRelease() = default;
  BackgroundRelease(const BackgroundRelease&) = delete;
  BackgroundRelease& operator=(const BackgroundRelease&) = delete;
  ~BackgroundRelease() {
    if (releasing_.valid()) releasing_.wait();
  }

  /// Takes `thing` (moved from) to be destroyed at the next release().
  template <class T>
  void keep(T&& thing) {
    static_assert(!std::is_lvalue_reference_v<T>, "keep takes what it is given: std::move it");
    kept_.push_back(std::make_shared<std::decay_t<T>>(std::move(thing)));
  }

  /// Destroys what was kept on a second thread (in line where no thread can be started).
  void release() {
    if (kept_.empty()) return;
    if (releasing_.valid()) releasing_.wait();
    std::vector<std::shared_ptr<void>> spent = std::move(kept_);
    kept_.clear();
    try {
      releasing_ = startInBackground([spent = std::move(spent)]() mutable { spent.clear(); });
    } catch (const std::system_error&) {
      spent.clear();
    }
  }

 private:
  std::vector<std::shared_ptr<void>> kept_;
  std::future<void> releasing_;
};

}  // namespace hydra_multi
