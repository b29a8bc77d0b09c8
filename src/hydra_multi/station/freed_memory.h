#pragma once
// Freed memory kept between backend rounds. jemalloc hands freed pages back to the system within
// about 10 s by default (blocks of 8 MB and more at once), so every backend round page-faults its
// graphs, problems and factors in afresh. keepFreedMemory makes it keep them (every arena's dirty
// decay off); trimFreedMemory, called after each round, hands them all back once they exceed a
// budget, so the process holds at most that much freed memory between rounds; and
// handBackFreedMemory, after the last round, restores jemalloc's decay. All leave the allocator as
// it is when the MALLOC_CONF environment variable is set (the user's choice) or the executables
// are built without jemalloc (HYDRA_MULTI_JEMALLOC off, the sanitizers). docs/DECISIONS.md: "Freed
// memory kept between rounds, up to 3 GB".

#include <cstddef>

namespace hydra_multi {

/// Whether jemalloc now keeps freed pages (false: left as it was). Call once, early.
bool keepFreedMemory();

struct FreedMemory {
  size_t bytes = 0;          ///< freed pages the allocator held (0 without jemalloc)
  bool handed_back = false;  ///< more than the budget: all handed back to the system
};

/// Hands every freed page back when they total more than `budget_bytes` (only while
/// keepFreedMemory keeps them).
FreedMemory trimFreedMemory(size_t budget_bytes);

/// Hands every freed page back and lets jemalloc hand later ones back as before keepFreedMemory
/// (after the station's last round: what follows is no round).
void handBackFreedMemory();

}  // namespace hydra_multi
