#include "hydra_multi/core/background_task.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>

namespace hydra_multi {
namespace {

// Linux keeps a nice value per thread; PRIO_PROCESS with a thread id reads or sets that thread's.
id_t thisThread() { return static_cast<id_t>(syscall(SYS_gettid)); }

}  // namespace

bool lowerThisThreadsPriority() { return setpriority(PRIO_PROCESS, thisThread(), 19) == 0; }

int thisThreadsNice() {
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, thisThread());
  return errno == 0 ? nice : 0;
}

}  // namespace hydra_multi
