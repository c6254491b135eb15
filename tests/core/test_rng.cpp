// Pcg32 is O'Neill's PCG32 (pcg-random.org, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation", 2014): checked against the reference implementation's published
// output, since a statistical test cannot see a lost constant or an even increment (which shortens the period).
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/rng.h"

namespace pt {
namespace {

TEST(Pcg32, MatchesTheReferenceImplementation) {
  // pcg32-demo of pcg-c-basic: pcg32_srandom_r(&rng, 42, 54), then six pcg32_random_r.
  Pcg32 rng(42, 54);
  for (uint32_t expected : {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u, 0x83d2f293u, 0xbfa4784bu, 0xcbed606eu})
    EXPECT_EQ(rng.next_u32(), expected);
}

TEST(Pcg32, EveryStreamHasAnOddIncrement) {
  // An LCG modulo 2^64 has its full period only with an odd increment (Hull-Dobell); stream s maps to 2 s + 1.
  for (uint64_t stream : {0ull, 1ull, 54ull, 0x8000000000000000ull, ~0ull}) EXPECT_EQ(Pcg32(7, stream).inc & 1u, 1u);
  std::set<uint64_t> incs;
  for (uint64_t stream : {0ull, 1ull, 2ull, 54ull}) incs.insert(Pcg32(7, stream).inc);
  EXPECT_EQ(incs.size(), 4u);
}

TEST(Pcg32, FloatsAre24BitsInTheHalfOpenUnitInterval) {
  Pcg32 rng(1, 2);
  for (int i = 0; i < 100000; ++i) {
    const float u = rng.next_float();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    ASSERT_EQ(u * 0x1p24f, std::floor(u * 0x1p24f));  // a multiple of 2^-24: exact, never rounded up to 1
  }
}

}  // namespace
}  // namespace pt
