#include <SuiteSparse_config.h>
#include <gtest/gtest.h>

#include <cstring>

#include "hydra_multi/optim/suitesparse_blocks.h"

namespace hydra_multi {
namespace {

// SuiteSparse's allocation functions, as CHOLMOD calls them once the blocks are kept.
void* allocate(size_t bytes) { return SuiteSparse_config.malloc_func(bytes); }
void release(void* block) { SuiteSparse_config.free_func(block); }

TEST(SuiteSparseBlocks, AFreedLargeBlockServesTheNextThatFits) {
  keepSuiteSparseBlocks();
  keepSuiteSparseBlocks();  // idempotent
  // Larger than any block the other tests' problems leave kept.
  const size_t large = 64 * kMinKeptBlockBytes;
  void* first = allocate(large);
  ASSERT_NE(first, nullptr);
  std::memset(first, 7, large);
  const KeptBlocks before = keptSuiteSparseBlocks();
  release(first);
  const KeptBlocks kept = keptSuiteSparseBlocks();
  EXPECT_EQ(kept.blocks, before.blocks + 1);
  EXPECT_EQ(kept.bytes, before.bytes + large + large / 4);

  const size_t capacity = large + large / 4;  // a new block has a quarter more room
  void* too_small = allocate(capacity + 1);   // does not fit: a new block
  EXPECT_NE(too_small, first);
  void* wasteful = allocate(capacity / 2 - 1);  // would waste more than it holds: a new block
  EXPECT_NE(wasteful, first);
  void* again = allocate(large + large / 8);  // grown, within the room
  EXPECT_EQ(again, first);
  EXPECT_EQ(keptSuiteSparseBlocks().reused, kept.reused + 1);
  for (void* b : {too_small, wasteful, again}) release(b);
}

TEST(SuiteSparseBlocks, CallocClearsAReusedBlockAndReallocKeepsTheContent) {
  keepSuiteSparseBlocks();
  const size_t large = 48 * kMinKeptBlockBytes;
  auto* block = static_cast<unsigned char*>(allocate(large));
  std::memset(block, 0xAB, large);
  release(block);
  auto* zeroed = static_cast<unsigned char*>(SuiteSparse_config.calloc_func(large / 8, 8));
  ASSERT_EQ(zeroed, block);  // the kept one, cleared
  for (size_t i = 0; i < large; i += 4093) ASSERT_EQ(zeroed[i], 0) << i;

  std::memset(zeroed, 0x5C, large);
  auto* grown = static_cast<unsigned char*>(SuiteSparse_config.realloc_func(zeroed, 3 * large));
  ASSERT_NE(grown, nullptr);
  for (size_t i = 0; i < large; i += 4093) ASSERT_EQ(grown[i], 0x5C) << i;
  // Shrinking within the block's capacity keeps it in place.
  EXPECT_EQ(SuiteSparse_config.realloc_func(grown, 2 * large), grown);
  release(grown);

  // Small blocks are malloc's, a small one grown large becomes a kept one on free.
  auto* small = static_cast<unsigned char*>(allocate(64));
  std::memset(small, 0x11, 64);
  auto* large_now = static_cast<unsigned char*>(SuiteSparse_config.realloc_func(small, large));
  ASSERT_NE(large_now, nullptr);
  EXPECT_EQ(large_now[63], 0x11);
  const size_t kept_before = keptSuiteSparseBlocks().blocks;
  release(large_now);
  EXPECT_EQ(keptSuiteSparseBlocks().blocks, kept_before + 1);
}

TEST(SuiteSparseBlocks, KeepsAtMostTheCapOldestFreedFirst) {
  keepSuiteSparseBlocks();
  const size_t big = kMaxKeptBytes / 3;
  void* blocks[4];
  for (void*& b : blocks) {
    b = allocate(big);
    ASSERT_NE(b, nullptr);
  }
  for (void* b : blocks) release(b);
  const KeptBlocks kept = keptSuiteSparseBlocks();
  EXPECT_LE(kept.bytes, kMaxKeptBytes);
  EXPECT_GE(kept.bytes, 2 * big);  // the two last freed
  // The oldest (blocks[0]) went back to the system; the newest is kept and served again.
  EXPECT_EQ(allocate(big), blocks[3]);
  release(blocks[3]);
}

// keptForReuse says which blocks a free keeps: from kMinKeptBlockBytes up to the largest whose
// quarter more room fits the cap (the blocks are allocated, never touched).
TEST(SuiteSparseBlocks, KeptForReuseSaysWhichBlocksAFreeKeeps) {
  keepSuiteSparseBlocks();
  EXPECT_FALSE(keptForReuse(kMinKeptBlockBytes - 1));
  EXPECT_TRUE(keptForReuse(kMinKeptBlockBytes));
  const size_t largest = kMaxKeptBytes / 5 * 4;
  EXPECT_TRUE(keptForReuse(largest));
  EXPECT_FALSE(keptForReuse(largest + 8));

  const KeptBlocks before = keptSuiteSparseBlocks();
  void* too_large = allocate(largest + 8);
  ASSERT_NE(too_large, nullptr);
  release(too_large);
  EXPECT_EQ(keptSuiteSparseBlocks().blocks, before.blocks);  // back to malloc
  EXPECT_EQ(keptSuiteSparseBlocks().bytes, before.bytes);

  void* kept = allocate(largest);
  ASSERT_NE(kept, nullptr);
  release(kept);
  EXPECT_EQ(keptSuiteSparseBlocks().bytes, largest + largest / 4);  // kept, the others evicted
  EXPECT_EQ(allocate(largest), kept);
  release(kept);
}

}  // namespace
}  // namespace hydra_multi
