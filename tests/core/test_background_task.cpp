// A background task runs on a thread of its own at the lowest priority and returns its work's
// result; the thread that started it keeps its own priority.

#include <gtest/gtest.h>

#include <memory>
#include <thread>
#include <utility>

#include "hydra_multi/core/background_task.h"

namespace hydra_multi {
namespace {

TEST(BackgroundTask, RunsOnItsOwnThreadAtTheLowestPriority) {
  const int caller_nice = thisThreadsNice();
  const std::thread::id caller = std::this_thread::get_id();
  auto task = startInBackground(
      [caller] { return std::make_pair(thisThreadsNice(), std::this_thread::get_id() != caller); });
  const auto [nice, elsewhere] = task.get();
  EXPECT_EQ(nice, 19);
  EXPECT_TRUE(elsewhere);
  EXPECT_EQ(thisThreadsNice(), caller_nice);
}

TEST(BackgroundTask, ThreadsItStartsInheritItsPriority) {
  auto task = startInBackground([] {
    int inner = -1;
    std::thread([&inner] { inner = thisThreadsNice(); }).join();
    return inner;
  });
  EXPECT_EQ(task.get(), 19);
}

TEST(BackgroundTask, TakesWhatItIsGivenAndReturnsTheWorksResult) {
  auto owned = std::make_unique<int>(41);
  auto task = startInBackground([owned = std::move(owned)]() mutable { return ++*owned; });
  EXPECT_EQ(task.get(), 42);
  auto nothing = startInBackground([] {});
  nothing.get();
}

}  // namespace
}  // namespace hydra_multi
