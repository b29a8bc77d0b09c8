#pragma once
// Work started now whose result is wanted later (a graph made while a solve runs, the next round's
// memory, freeing what a round is done with): run on a thread of its own at the lowest CPU
// priority (on Linux, nice 19 for that thread alone; threads it starts inherit it). Where busy
// threads outnumber cores it takes the time the others leave idle, and a thread that waits for
// its result gives it that thread's core. The result does not depend on the priority.

#include <future>
#include <type_traits>
#include <utility>

namespace hydra_multi {

/// Gives the calling thread the lowest CPU priority; the process's other threads keep theirs.
/// Returns false where the system refuses (the thread then runs as before).
bool lowerThisThreadsPriority();

/// The calling thread's nice value (-20 .. 19; 0 where it cannot be read).
int thisThreadsNice();

/// work() on a new thread at the lowest priority (std::async with std::launch::async).
template <class Work>
std::future<std::invoke_result_t<std::decay_t<Work>&>> startInBackground(Work&& work) {
  return std::async(std::launch::async, [work = std::forward<Work>(work)]() mutable {
    lowerThisThreadsPriority();
    return work();
  });
}

}  // namespace hydra_multi
