#pragma once
// SuiteSparse's large blocks kept for reuse. CHOLMOD allocates its factor and workspace (hundreds
// of MB at team scale) for every problem and frees them after; glibc maps such blocks afresh each
// time and unmaps them on free (in the backend's thread always: its arena maps blocks over 64 MB),
// so the first factorization of each problem page-faults through the whole factor. Once installed,
// SuiteSparse's allocations of at least kMinKeptBlockBytes come from blocks freed earlier where one
// fits (capacity between the size and twice it, the smallest such, the last freed of equal ones),
// a new one with a quarter more room than asked (untouched pages cost no memory), and its frees
// keep such blocks while the kept ones total at most kMaxKeptBytes (the oldest freed first).
// Smaller blocks, and blocks allocated before installing, go to malloc and free as before. A block
// reused for calloc is cleared. Thread-safe. docs/DECISIONS.md: "CHOLMOD's large blocks
// kept for reuse".

#include <cstddef>

namespace hydra_multi {

constexpr size_t kMinKeptBlockBytes = size_t{1} << 20;
constexpr size_t kMaxKeptBytes = size_t{1} << 30;

/// SuiteSparse_config's malloc, calloc, realloc and free replaced by the kept blocks' (above).
/// Idempotent; call before SuiteSparse allocates.
void keepSuiteSparseBlocks();

/// Whether a block of `bytes` is one the installed keeper hands on to the next allocation it fits
/// when freed, whichever thread allocated it (at least kMinKeptBlockBytes, its capacity within
/// kMaxKeptBytes).
bool keptForReuse(size_t bytes);

/// What the kept blocks hold now, and how many allocations they served (for tests and benchmarks).
struct KeptBlocks {
  size_t blocks = 0, bytes = 0, reused = 0;
};
KeptBlocks keptSuiteSparseBlocks();

}  // namespace hydra_multi
