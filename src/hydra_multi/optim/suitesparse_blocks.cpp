#include "hydra_multi/optim/suitesparse_blocks.h"

#include <SuiteSparse_config.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace hydra_multi {
namespace {

// A new block's capacity: a quarter more room than asked, as the next problem's factor is a little
// larger than this one's (pages of the room are never touched unless used).
size_t withRoom(size_t bytes) { return bytes + bytes / 4; }

struct Kept {
  void* block;
  size_t capacity;
};

class BlockKeeper {
 public:
  void* allocate(size_t bytes, bool zero) {
    if (bytes >= kMinKeptBlockBytes) {
      std::lock_guard<std::mutex> lock(mutex_);
      // The smallest kept block that fits without wasting more than the request (of equal ones,
      // the last freed).
      size_t best = kept_.size();
      for (size_t i = 0; i < kept_.size(); ++i) {
        const size_t c = kept_[i].capacity;
        if (c >= bytes && c / 2 <= bytes && (best == kept_.size() || c <= kept_[best].capacity))
          best = i;
      }
      if (best != kept_.size()) {
        const Kept k = kept_[best];
        kept_.erase(kept_.begin() + static_cast<std::ptrdiff_t>(best));
        kept_bytes_ -= k.capacity;
        live_[k.block] = k.capacity;
        ++reused_;
        if (zero) std::memset(k.block, 0, bytes);
        return k.block;
      }
    }
    if (bytes < kMinKeptBlockBytes) return zero ? std::calloc(bytes, 1) : std::malloc(bytes);
    const size_t capacity = withRoom(bytes);
    void* block = zero ? std::calloc(capacity, 1) : std::malloc(capacity);
    if (block != nullptr) {
      std::lock_guard<std::mutex> lock(mutex_);
      live_[block] = capacity;
    }
    return block;
  }

  void release(void* block) {
    if (block == nullptr) return;
    std::unique_lock<std::mutex> lock(mutex_);
    const auto live = live_.find(block);
    const size_t capacity = live == live_.end() ? 0 : live->second;
    if (capacity == 0 || capacity > kMaxKeptBytes) {  // small, not ours, or too large to keep
      if (capacity != 0) live_.erase(live);
      lock.unlock();
      std::free(block);
      return;
    }
    live_.erase(live);
    kept_.push_back({block, capacity});
    kept_bytes_ += capacity;
    std::vector<void*> evicted;  // freed outside the lock
    while (kept_bytes_ > kMaxKeptBytes) {
      kept_bytes_ -= kept_.front().capacity;
      evicted.push_back(kept_.front().block);
      kept_.pop_front();
    }
    lock.unlock();
    for (void* b : evicted) std::free(b);
  }

  void* resize(void* block, size_t bytes) {
    if (block == nullptr) return allocate(bytes, false);
    size_t capacity = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto live = live_.find(block);
      if (live != live_.end()) capacity = live->second;
    }
    if (capacity == 0) {  // a small block of ours, or not ours: malloc knows its size
      void* grown = std::realloc(block, bytes);
      if (grown != nullptr && bytes >= kMinKeptBlockBytes) {
        std::lock_guard<std::mutex> lock(mutex_);
        live_[grown] = bytes;
      }
      return grown;
    }
    if (bytes <= capacity && capacity / 2 <= bytes) return block;
    void* moved = allocate(bytes, false);
    if (moved == nullptr) return nullptr;  // SuiteSparse keeps the old block
    std::memcpy(moved, block, capacity < bytes ? capacity : bytes);
    release(block);
    return moved;
  }

  KeptBlocks state() {
    std::lock_guard<std::mutex> lock(mutex_);
    return {kept_.size(), kept_bytes_, reused_};
  }

 private:
  std::mutex mutex_;
  std::unordered_map<void*, size_t> live_;  // large blocks handed out, with their capacity
  std::deque<Kept> kept_;                   // freed large blocks, oldest first
  size_t kept_bytes_ = 0, reused_ = 0;
};

BlockKeeper& keeper() {
  static BlockKeeper* k = new BlockKeeper;  // never destroyed: SuiteSparse may free at exit
  return *k;
}

void* keptMalloc(size_t bytes) { return keeper().allocate(bytes, false); }
void* keptCalloc(size_t count, size_t size) {
  if (size != 0 && count > SIZE_MAX / size) return nullptr;
  return keeper().allocate(count * size, true);
}
void* keptRealloc(void* block, size_t bytes) { return keeper().resize(block, bytes); }
void keptFree(void* block) { keeper().release(block); }

}  // namespace

void keepSuiteSparseBlocks() {
  static std::once_flag once;
  std::call_once(once, [] {
    keeper();
    SuiteSparse_config.malloc_func = keptMalloc;
    SuiteSparse_config.calloc_func = keptCalloc;
    SuiteSparse_config.realloc_func = keptRealloc;
    SuiteSparse_config.free_func = keptFree;
  });
}

bool keptForReuse(size_t bytes) {
  return bytes >= kMinKeptBlockBytes && withRoom(bytes) <= kMaxKeptBytes;
}

KeptBlocks keptSuiteSparseBlocks() { return keeper().state(); }

}  // namespace hydra_multi
