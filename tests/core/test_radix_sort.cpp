// The radix sort (src/core/radix_sort.h): the same order as std::stable_sort by the bits from low_bit up, for keys
// that share high digits (skipped passes), differ only in them, or repeat; empty and single-key inputs.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/radix_sort.h"
#include "core/rng.h"

namespace pt {
namespace {

void expect_stable_sorted(std::vector<uint64_t> keys, int low_bit) {
  std::vector<uint64_t> expected = keys;
  auto high = [&](uint64_t k) { return low_bit == 64 ? 0 : k >> low_bit; };
  std::stable_sort(expected.begin(), expected.end(), [&](uint64_t a, uint64_t b) { return high(a) < high(b); });
  radix_sort(keys, low_bit);
  EXPECT_EQ(keys, expected) << "low bit " << low_bit;
}

TEST(RadixSort, OrdersLikeAStableSortOfTheHighBits) {
  Pcg32 rng(5, 1);
  for (int low_bit : {0, 1, 11, 32, 40, 63}) {
    for (int shape = 0; shape < 4; ++shape) {
      std::vector<uint64_t> keys(5000);
      for (size_t i = 0; i < keys.size(); ++i) {
        const uint64_t r = uint64_t(rng.next_u32()) << 32 | rng.next_u32();
        switch (shape) {
          case 0:
            keys[i] = r;
            break;  // any bits
          case 1:
            keys[i] = (r % 7) << 40 | i;
            break;  // few values above, order below
          case 2:
            keys[i] = 0xabcd000000000000ull | (r & 0xffffff);
            break;  // high digits shared
          default:
            keys[i] = (r & 0xfff0000000000000ull) | i;
            break;  // only the top digit varies
        }
      }
      expect_stable_sorted(keys, low_bit);
    }
  }
  expect_stable_sorted({}, 0);
  expect_stable_sorted({42}, 0);
  expect_stable_sorted({3, 1, 2}, 64);
}

}  // namespace
}  // namespace pt
