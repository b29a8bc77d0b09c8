#include "hydra_multi/optim/serial_openmp.h"

#include <dlfcn.h>

extern "C" {
void omp_set_max_active_levels(int max_levels);  // OpenMP's API, as libgomp exports it
int omp_get_max_active_levels(void);
}

namespace hydra_multi {
namespace {

using ParallelEntry = void (*)(void (*)(void*), void*, unsigned, unsigned);

thread_local int serial_depth = 0;  // SerialOpenMp objects alive on this thread

ParallelEntry libgompParallel() {
  static const ParallelEntry entry =
      reinterpret_cast<ParallelEntry>(dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0"));
  return entry;
}

}  // namespace

SerialOpenMp::SerialOpenMp() : saved_(omp_get_max_active_levels()) {
  omp_set_max_active_levels(0);
  ++serial_depth;
}

SerialOpenMp::~SerialOpenMp() {
  --serial_depth;
  omp_set_max_active_levels(saved_);
}

}  // namespace hydra_multi

// GCC's OpenMP ABI (libgomp 4.0 on): run `fn(data)` on a team of `num_threads`. Without a team
// libgomp's worksharing, single and barrier calls act as for one thread, so calling `fn` directly
// is the same region on this thread alone. Without libgomp's entry (none found) likewise.
extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags) {
  if (hydra_multi::serial_depth > 0) return fn(data);  // CHOLMOD's regions: this check alone
  const hydra_multi::ParallelEntry libgomp = hydra_multi::libgompParallel();
  if (libgomp == nullptr) return fn(data);
  libgomp(fn, data, num_threads, flags);
}
