#include "hydra_multi/station/freed_memory.h"

#include <sys/types.h>

#include <cstdint>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>

#ifdef HYDRA_MULTI_JEMALLOC
#include <jemalloc/jemalloc.h>
#endif

namespace hydra_multi {
namespace {

#ifdef HYDRA_MULTI_JEMALLOC
std::mutex mutex;
bool kept = false;
ssize_t default_decay_ms = 0;                // jemalloc's default before keepFreedMemory
std::map<unsigned, ssize_t> arena_decay_ms;  // each arena's then

bool setDecay(const std::string& name, ssize_t ms, ssize_t* before = nullptr) {
  size_t size = sizeof(ssize_t);
  return mallctl(name.c_str(), before, before != nullptr ? &size : nullptr, &ms, sizeof(ms)) == 0;
}

unsigned arenaCount() {
  unsigned arenas = 0;
  size_t size = sizeof(arenas);
  return mallctl("arenas.narenas", &arenas, &size, nullptr, 0) == 0 ? arenas : 0;
}

std::string arenaDecay(unsigned arena) {
  return "arena." + std::to_string(arena) + ".dirty_decay_ms";
}

const std::string kEveryArena = std::to_string(MALLCTL_ARENAS_ALL);  // in names: all, summed

bool purgeEveryArena() {
  return mallctl(("arena." + kEveryArena + ".purge").c_str(), nullptr, nullptr, nullptr, 0) == 0;
}
#endif

}  // namespace

bool keepFreedMemory() {
#ifdef HYDRA_MULTI_JEMALLOC
  const std::lock_guard<std::mutex> lock(mutex);
  if (kept) return true;
  if (std::getenv("MALLOC_CONF") != nullptr) return false;
  // Arenas made from now on (the one for large blocks among them), then those made already (one
  // not initialized yet answers an error: it will be made with the new default).
  if (!setDecay("arenas.dirty_decay_ms", -1, &default_decay_ms)) return false;
  arena_decay_ms.clear();
  for (unsigned i = 0, n = arenaCount(); i < n; ++i) {
    ssize_t before = 0;
    if (setDecay(arenaDecay(i), -1, &before)) arena_decay_ms[i] = before;
  }
  kept = true;
  return true;
#else
  return false;
#endif
}

void handBackFreedMemory() {
#ifdef HYDRA_MULTI_JEMALLOC
  const std::lock_guard<std::mutex> lock(mutex);
  if (!kept) return;
  setDecay("arenas.dirty_decay_ms", default_decay_ms);
  for (unsigned i = 0, n = arenaCount(); i < n; ++i) {
    const auto before = arena_decay_ms.find(i);
    setDecay(arenaDecay(i), before != arena_decay_ms.end() ? before->second : default_decay_ms);
  }
  purgeEveryArena();
  kept = false;
#endif
}

FreedMemory trimFreedMemory(size_t budget_bytes) {
  FreedMemory freed;
#ifdef HYDRA_MULTI_JEMALLOC
  const std::lock_guard<std::mutex> lock(mutex);
  uint64_t epoch = 1;  // refreshes the statistics
  size_t size = sizeof(epoch);
  if (mallctl("epoch", &epoch, &size, &epoch, size) != 0) return freed;
  size_t pages = 0, page = 0;
  size = sizeof(pages);
  if (mallctl(("stats.arenas." + kEveryArena + ".pdirty").c_str(), &pages, &size, nullptr, 0) != 0)
    return freed;
  size = sizeof(page);
  if (mallctl("arenas.page", &page, &size, nullptr, 0) != 0) return freed;
  freed.bytes = pages * page;
  if (kept && freed.bytes > budget_bytes) freed.handed_back = purgeEveryArena();
#else
  (void)budget_bytes;
#endif
  return freed;
}

}  // namespace hydra_multi
