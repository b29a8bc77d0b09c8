#pragma once
// Fork-join over a few threads: work(t) for t = 0 .. threads-1, t = 0 on the calling thread and
// each other on a thread of its own, all joined before the call returns. The caller splits the
// work so that no two t write the same memory; what each t computes then does not depend on the
// number of threads.

#include <cstddef>
#include <thread>
#include <vector>

namespace hydra_multi {

template <typename Work>
void runOnThreads(size_t threads, const Work& work) {
  std::vector<std::thread> helpers;
  for (size_t t = 1; t < threads; ++t) helpers.emplace_back([&work, t] { work(t); });
  work(0);
  for (std::thread& helper : helpers) helper.join();
}

}  // namespace hydra_multi
