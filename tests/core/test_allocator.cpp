// The executables' allocator: built with HYDRA_MULTI_JEMALLOC, malloc is jemalloc's, so its count
// of the bytes this thread allocated grows by what malloc hands out, and it runs with the options
// the executables give it (core/jemalloc_options.cpp) unless MALLOC_CONF says otherwise.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>

#ifdef HYDRA_MULTI_JEMALLOC
#include <jemalloc/jemalloc.h>
#endif

namespace {

TEST(Allocator, MallocIsJemallocWhenLinked) {
#ifndef HYDRA_MULTI_JEMALLOC
  GTEST_SKIP() << "built without jemalloc (HYDRA_MULTI_JEMALLOC off, or under the sanitizers)";
#else
  const auto allocated = [] {
    uint64_t bytes = 0;
    size_t size = sizeof(bytes);
    EXPECT_EQ(mallctl("thread.allocated", &bytes, &size, nullptr, 0), 0);
    return bytes;
  };
  const uint64_t before = allocated();
  constexpr size_t kBytes = 1 << 20;
  auto* volatile block = static_cast<char*>(std::malloc(kBytes));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBytes);
  const uint64_t after = allocated();
  std::free(block);
  EXPECT_GE(after - before, kBytes);
#endif
}

TEST(Allocator, JemallocAsksForTransparentHugePages) {
#ifndef HYDRA_MULTI_JEMALLOC
  GTEST_SKIP() << "built without jemalloc (HYDRA_MULTI_JEMALLOC off, or under the sanitizers)";
#else
  if (std::getenv("MALLOC_CONF") != nullptr) GTEST_SKIP() << "MALLOC_CONF set: the user's options";
  const char* thp = nullptr;
  size_t size = sizeof(thp);
  ASSERT_EQ(mallctl("opt.thp", &thp, &size, nullptr, 0), 0);
  EXPECT_STREQ(thp, "always");
#endif
}

}  // namespace
