// Freed memory kept between backend rounds (station/freed_memory.h): once kept, a large block's
// pages stay with the allocator after it is freed, even in the arena that held them before
// (jemalloc's for blocks of 8 MB and more, which otherwise hands them back at once), until a trim
// finds more than its budget; after the hand-back they go back at once again.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "hydra_multi/station/freed_memory.h"

namespace hydra_multi {
namespace {

constexpr size_t kBlock = size_t{32} << 20;

void allocateTouchAndFree() {
  auto* volatile block = static_cast<char*>(std::malloc(kBlock));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlock);
  std::free(block);
}

TEST(FreedMemory, KeptUntilABudgetThenHandedBack) {
#ifndef HYDRA_MULTI_JEMALLOC
  EXPECT_FALSE(keepFreedMemory());
  EXPECT_EQ(trimFreedMemory(0).bytes, 0u);
  GTEST_SKIP() << "built without jemalloc (HYDRA_MULTI_JEMALLOC off, or under the sanitizers)";
#else
  if (std::getenv("MALLOC_CONF") != nullptr) {
    EXPECT_FALSE(keepFreedMemory());
    GTEST_SKIP() << "MALLOC_CONF is set: the allocator is left as set";
  }
  allocateTouchAndFree();  // its arena made before keepFreedMemory
  ASSERT_TRUE(keepFreedMemory());
  const size_t before = trimFreedMemory(SIZE_MAX).bytes;
  allocateTouchAndFree();
  const FreedMemory kept = trimFreedMemory(SIZE_MAX);
  EXPECT_FALSE(kept.handed_back);
  EXPECT_GE(kept.bytes, before + kBlock);
  const FreedMemory trimmed = trimFreedMemory(kept.bytes - 1);
  EXPECT_TRUE(trimmed.handed_back);
  EXPECT_GE(trimmed.bytes, kBlock);
  EXPECT_LT(trimFreedMemory(SIZE_MAX).bytes, kBlock);
  // After the last round: handed back as before keepFreedMemory, at once for such a block.
  handBackFreedMemory();
  allocateTouchAndFree();
  const FreedMemory after = trimFreedMemory(0);
  EXPECT_FALSE(after.handed_back);
  EXPECT_LT(after.bytes, kBlock);
#endif
}

}  // namespace
}  // namespace hydra_multi
