// The huge-page allocator's block cache (src/core/huge_page_allocator.h): a freed huge block is handed back for a
// request of exactly its size and for no other, the cache never holds more than its cap, and small allocations
// never enter it.
#include <gtest/gtest.h>

#include "core/huge_page_allocator.h"

namespace pt {
namespace {

constexpr size_t kPage = HugePageAllocator<char>::kHugePage;

TEST(HugeBlockCache, AFreedBlockComesBackForItsOwnSizeOnly) {
  HugePageAllocator<char> a;
  char* p = a.allocate(3 * kPage - 5);  // rounded up to 3 pages
  p[0] = 1;
  const size_t before = huge_block_cache::held_bytes();
  a.deallocate(p, 3 * kPage - 5);
  EXPECT_EQ(huge_block_cache::held_bytes(), before + 3 * kPage);
  char* other = a.allocate(2 * kPage);  // another size: a fresh block
  EXPECT_NE(other, p);
  char* same = a.allocate(3 * kPage - 1);  // the same number of pages: the cached block
  EXPECT_EQ(same, p);
  EXPECT_EQ(huge_block_cache::held_bytes(), before);
  a.deallocate(other, 2 * kPage);
  a.deallocate(same, 3 * kPage - 1);
}

// Of two cached blocks of one size, the one freed last comes back first: it is the likelier to be in the CPU's caches
// still (huge_page_allocator.cpp, take).
TEST(HugeBlockCache, TheNewestBlockOfASizeComesBackFirst) {
  HugePageAllocator<char> a;
  char* older = a.allocate(5 * kPage);
  char* newer = a.allocate(5 * kPage);
  older[0] = newer[0] = 1;
  a.deallocate(older, 5 * kPage);
  a.deallocate(newer, 5 * kPage);
  char* first = a.allocate(5 * kPage);
  char* second = a.allocate(5 * kPage);
  EXPECT_EQ(first, newer);
  EXPECT_EQ(second, older);
  a.deallocate(first, 5 * kPage);
  a.deallocate(second, 5 * kPage);
}

TEST(HugeBlockCache, NeverHoldsMoreThanItsCap) {
  HugePageAllocator<char> a;
  const size_t block = 64 * kPage;  // 128 MiB, not touched: costs no memory
  std::vector<char*> blocks;
  for (int i = 0; i < 5; ++i) blocks.push_back(a.allocate(block));
  for (char* p : blocks) a.deallocate(p, block);
  EXPECT_LE(huge_block_cache::held_bytes(), huge_block_cache::kMaxBytes);
  EXPECT_GE(huge_block_cache::held_bytes(), 2 * block);  // the newest two stay
  // A block that takes two older ones out to fit under the cap: both go, and it stays.
  char* big = a.allocate(100 * kPage);
  a.deallocate(big, 100 * kPage);
  EXPECT_LE(huge_block_cache::held_bytes(), huge_block_cache::kMaxBytes);
  EXPECT_GE(huge_block_cache::held_bytes(), 100 * kPage);
  // A block larger than the cap is freed at once.
  const size_t held = huge_block_cache::held_bytes();
  char* huge = a.allocate(huge_block_cache::kMaxBytes + kPage);
  a.deallocate(huge, huge_block_cache::kMaxBytes + kPage);
  EXPECT_EQ(huge_block_cache::held_bytes(), held);
  huge_block_cache::release_all();
  EXPECT_EQ(huge_block_cache::held_bytes(), 0u);
}

TEST(HugeBlockCache, SmallAllocationsBypassIt) {
  HugePageAllocator<double> a;
  const size_t before = huge_block_cache::held_bytes();
  double* p = a.allocate(100);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % 64, 0u);
  a.deallocate(p, 100);
  EXPECT_EQ(huge_block_cache::held_bytes(), before);
}

}  // namespace
}  // namespace pt
