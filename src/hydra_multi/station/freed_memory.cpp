#include "hydra_multi/station/freed_memory.h"

#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <string>

#ifdef HYDRA_MULTI_JEMALLOC
#include <jemalloc/jemalloc.h>
#endif

namespace hydra_multi {
namespace {

std::atomic<bool> kept{false};

}  // namespace

bool keepFreedMemory() {
#ifdef HYDRA_MULTI_JEMALLOC
  if (kept) return true;
  if (std::getenv("MALLOC_CONF") != nullptr) return false;
  ssize_t never = -1;
  // Arenas made from now on (the one for large blocks among them), then those made already.
  if (mallctl("arenas.dirty_decay_ms", nullptr, nullptr, &never, sizeof(never)) != 0) return false;
  unsigned arenas = 0;
  size_t size = sizeof(arenas);
  if (mallctl("arenas.narenas", &arenas, &size, nullptr, 0) != 0) return false;
  for (unsigned i = 0; i < arenas; ++i) {
    // An arena not initialized yet answers an error; it will be made with the new default.
    const std::string name = "arena." + std::to_string(i) + ".dirty_decay_ms";
    mallctl(name.c_str(), nullptr, nullptr, &never, sizeof(never));
  }
  kept = true;
  return true;
#else
  return false;
#endif
}

FreedMemory trimFreedMemory(size_t budget_bytes) {
  FreedMemory freed;
#ifdef HYDRA_MULTI_JEMALLOC
  if (!kept) return freed;
  uint64_t epoch = 1;  // refreshes the statistics
  size_t size = sizeof(epoch);
  if (mallctl("epoch", &epoch, &size, &epoch, size) != 0) return freed;
  const std::string every = std::to_string(MALLCTL_ARENAS_ALL);  // every arena's, summed
  size_t pages = 0, page = 0;
  size = sizeof(pages);
  if (mallctl(("stats.arenas." + every + ".pdirty").c_str(), &pages, &size, nullptr, 0) != 0)
    return freed;
  size = sizeof(page);
  if (mallctl("arenas.page", &page, &size, nullptr, 0) != 0) return freed;
  freed.bytes = pages * page;
  if (freed.bytes > budget_bytes)
    freed.handed_back =
        mallctl(("arena." + every + ".purge").c_str(), nullptr, nullptr, nullptr, 0) == 0;
#else
  (void)budget_bytes;
#endif
  return freed;
}

}  // namespace hydra_multi
