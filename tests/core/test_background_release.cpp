// What is kept lives until release() and is then destroyed on another thread; the destructor waits
// for it, and each release for the one before.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

#include "hydra_multi/core/background_release.h"

namespace hydra_multi {
namespace {

// Records on which thread it was destroyed, and that it was.
struct Tracked {
  std::atomic<int>* destroyed;
  std::thread::id* destroyed_on;
  std::chrono::milliseconds linger{0};
  Tracked(std::atomic<int>* d, std::thread::id* on, std::chrono::milliseconds l = {})
      : destroyed(d), destroyed_on(on), linger(l) {}
  Tracked(Tracked&& other) noexcept
      : destroyed(std::exchange(other.destroyed, nullptr)),
        destroyed_on(other.destroyed_on),
        linger(other.linger) {}
  ~Tracked() {
    if (destroyed == nullptr) return;  // moved from
    std::this_thread::sleep_for(linger);
    *destroyed_on = std::this_thread::get_id();
    ++*destroyed;
  }
};

TEST(BackgroundRelease, KeptUntilReleasedThenDestroyedOnAnotherThread) {
  std::atomic<int> destroyed{0};
  std::thread::id on;
  {
    BackgroundRelease release;
    release.keep(Tracked(&destroyed, &on));
    release.keep(std::vector<int>(1000, 7));
    EXPECT_EQ(destroyed.load(), 0);
    release.release();
  }  // the destructor waits for the release
  EXPECT_EQ(destroyed.load(), 1);
  EXPECT_NE(on, std::this_thread::get_id());
}

TEST(BackgroundRelease, EachReleaseWaitsForTheOneBefore) {
  std::atomic<int> destroyed{0};
  std::thread::id first_on, second_on;
  BackgroundRelease release;
  release.keep(Tracked(&destroyed, &first_on, std::chrono::milliseconds(50)));
  release.release();
  release.keep(Tracked(&destroyed, &second_on));
  release.release();  // returns once the first release is done
  EXPECT_GE(destroyed.load(), 1);
  release.release();  // nothing kept: nothing to do
}

TEST(BackgroundRelease, WhatIsNeverReleasedGoesWithIt) {
  std::atomic<int> destroyed{0};
  std::thread::id on;
  {
    BackgroundRelease release;
    release.release();  // nothing kept: nothing started
    release.keep(Tracked(&destroyed, &on));
    EXPECT_EQ(destroyed.load(), 0);
  }
  EXPECT_EQ(destroyed.load(), 1);
  EXPECT_EQ(on, std::this_thread::get_id());
}

}  // namespace
}  // namespace hydra_multi
