// The shuffled Owen-scrambled Sobol sampler keeps the (0, k, 2)-net property for every power-of-two prefix, which
// is what makes it converge faster than independent samples.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "core/sobol.h"
#include "net_check.h"

namespace pt {
namespace {

using test::is_net;

TEST(Sobol, EveryPowerOfTwoPrefixIsANet) {
  for (uint32_t seed : {0u, 1u, 12345u, 0xdeadbeefu})
    for (int k = 0; k <= 10; ++k) {
      std::vector<vec2> pts;
      for (uint32_t i = 0; i < (1u << k); ++i) pts.push_back(sobol_owen_2d(i, seed));
      EXPECT_TRUE(is_net(pts, k)) << "seed " << seed << " k " << k;
      // ...and so is the next block of 2^k.
      std::vector<vec2> next;
      for (uint32_t i = 1u << k; i < (2u << k); ++i) next.push_back(sobol_owen_2d(i, seed));
      EXPECT_TRUE(is_net(next, k)) << "seed " << seed << " k " << k;
    }
}

TEST(Sobol, OneDimensionIsStratified) {
  for (uint32_t seed : {3u, 77u})
    for (int k = 0; k <= 12; ++k) {
      std::set<int> cells;
      for (uint32_t i = 0; i < (1u << k); ++i) cells.insert(int(sobol_owen_1d(i, seed) * float(1 << k)));
      EXPECT_EQ(cells.size(), size_t(1) << k);
    }
}

TEST(Sobol, DirectionNumbersGiveTheKnownFirstPoints) {
  // The first points of the 4D Sobol sequence (Joe-Kuo parameters) in natural index order.
  const double expected[8][4] = {{0, 0, 0, 0},          {0.5, 0.5, 0.5, 0.5},         {0.25, 0.75, 0.75, 0.75},
                                 {0.75, 0.25, 0.25, 0.25}, {0.125, 0.625, 0.375, 0.125}, {0.625, 0.125, 0.875, 0.625},
                                 {0.375, 0.375, 0.625, 0.875}, {0.875, 0.875, 0.125, 0.375}};
  for (uint32_t i = 0; i < 8; ++i)
    for (int d = 0; d < 4; ++d) EXPECT_EQ(sobol_reference(i, d) * 0x1p-32, expected[i][d]) << "index " << i << " dim " << d;
}

TEST(Sobol, DirectionNumbersFollowTheirPrimitivePolynomials) {
  // The first eight points above check only the initial direction integers m_1..m_3; every index bit from 3 up
  // comes from the recurrence over the primitive polynomial (Bratley and Fox 1988, eq. (2); Joe and Kuo 2008).
  // m_1..m_16 of dimensions 1-3 (polynomials x + 1, x^2 + x + 1, x^3 + x + 1 with the Joe-Kuo initial values),
  // written out as the published recurrence gives them:
  const uint32_t m[3][16] = {
      {1, 3, 5, 15, 17, 51, 85, 255, 257, 771, 1285, 3855, 4369, 13107, 21845, 65535},
      {1, 3, 3, 9, 29, 23, 71, 197, 209, 627, 1907, 1369, 4109, 12327, 12407, 36949},
      {1, 3, 1, 5, 31, 29, 81, 147, 433, 149, 719, 3693, 3841, 11523, 16641, 49925}};
  const auto& v = sobol_detail::kDirections;
  for (int d = 1; d < 4; ++d)
    for (int j = 0; j < 16; ++j) EXPECT_EQ(v[size_t(d)][size_t(j)], m[d - 1][j] << (31 - j)) << "dim " << d << " bit " << j;
  // All 32 by the recurrence in its fixed-point form: v_i = v_{i-s} ^ (v_{i-s} >> s) ^ a_k v_{i-k} (k = 1..s-1).
  const int degree[4] = {0, 1, 2, 3};
  const uint32_t coefficients[4] = {0, 0, 1, 1};
  for (int d = 1; d < 4; ++d) {
    const int s = degree[d];
    for (int i = s; i < 32; ++i) {
      uint32_t want = v[size_t(d)][size_t(i - s)] ^ (v[size_t(d)][size_t(i - s)] >> s);
      for (int k = 1; k < s; ++k)
        if ((coefficients[d] >> (s - 1 - k)) & 1u) want ^= v[size_t(d)][size_t(i - k)];
      EXPECT_EQ(v[size_t(d)][size_t(i)], want) << "dim " << d << " bit " << i;
    }
  }
  // Dimension 0 is the van der Corput sequence: bit j of the index is worth 2^-(j+1).
  for (int j = 0; j < 32; ++j) EXPECT_EQ(v[0][size_t(j)], 1u << (31 - j));
}

TEST(Sobol, ByteTablesMatchTheDefinitionOnTheTop24Bits) {
  // The fast path reads the bit-reversed index a byte at a time, index bits 0-23; it must equal the plain XOR of
  // direction numbers for every index below 2^24 (small ones and random ones).
  uint32_t x = 12345u;
  for (int n = 0; n < 20000; ++n) {
    x = hash_u32(x + uint32_t(n));
    uint32_t index = n < 4096 ? uint32_t(n) : x & 0xffffffu;
    for (int d = 0; d < 4; ++d) {
      uint32_t fast = reverse_bits(sobol_reversed(reverse_bits(index), d));
      ASSERT_EQ(fast, sobol_reference(index, d)) << "index " << index << " dim " << d;
    }
  }
}

/// The pattern as first written (dimension 0 by a double bit reversal, each dimension on its own): the fast forms
/// must give exactly these numbers, so images do not change with the implementation.
void first_definition(uint32_t index, uint32_t seed, float* out) {
  const uint32_t r = laine_karras_permutation(reverse_bits(index), seed);
  out[0] = fixed_to_unit_float(reverse_bits(laine_karras_permutation(reverse_bits(r), hash_u32(seed + 0x9e3779b9u))));
  for (int k = 1; k < 4; ++k)
    out[k] = fixed_to_unit_float(
        reverse_bits(laine_karras_permutation(sobol_reversed(r, k), hash_u32(seed + 0x9e3779b9u * uint32_t(k + 1)))));
}

TEST(Sobol, FastPatternsGiveExactlyTheDefinedNumbers) {
  uint32_t x = 777u;
  for (int n = 0; n < 200000; ++n) {
    x = hash_u32(x + uint32_t(n));
    const uint32_t index = n < 4096 ? uint32_t(n) : x & 0xffffffu, seed = hash_u32(x ^ 0x5bd1e995u);
    float want[4], scalar[4], simd[4], simd3[3], simd2[2], simd1[1];
    first_definition(index, seed, want);
    sobol_owen_pattern_scalar<4>(reverse_bits(index), seed, scalar);
    sobol_owen_pattern<4>(reverse_bits(index), seed, simd);
    sobol_owen_pattern<3>(reverse_bits(index), seed, simd3);
    sobol_owen_pattern<2>(reverse_bits(index), seed, simd2);
    sobol_owen_pattern<1>(reverse_bits(index), seed, simd1);
    for (int d = 0; d < 4; ++d) {
      ASSERT_EQ(scalar[d], want[d]) << "scalar, index " << index << " seed " << seed << " dim " << d;
      ASSERT_EQ(simd[d], want[d]) << "simd, index " << index << " seed " << seed << " dim " << d;
    }
    for (int d = 0; d < 3; ++d) ASSERT_EQ(simd3[d], want[d]);
    for (int d = 0; d < 2; ++d) ASSERT_EQ(simd2[d], want[d]);
    ASSERT_EQ(simd1[0], want[0]);
  }
}

#if defined(__SSE4_1__) && defined(__SSSE3__)
TEST(Sobol, VectorBitReversalsMatchTheScalarOne) {
  // Both byte-level reversals (GFNI where the build has it, the nibble lookups always), on every lane.
  uint32_t x = 99u;
  for (int n = 0; n < 100000; ++n) {
    uint32_t in[4], out[4], nib[4];
    for (uint32_t& v : in) v = x = hash_u32(x + uint32_t(n));
    if (n < 64) in[n % 4] = 1u << (n / 2);  // single bits too
    __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), sobol_detail::reverse_bits4(v));
    const __m128i bswap = _mm_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(nib),
                     sobol_detail::reverse_bits_in_bytes_by_nibbles(_mm_shuffle_epi8(v, bswap)));
    for (int k = 0; k < 4; ++k) {
      ASSERT_EQ(out[k], reverse_bits(in[k])) << in[k];
      ASSERT_EQ(nib[k], reverse_bits(in[k])) << in[k];
    }
  }
}
#endif

TEST(Sobol, EveryDimensionOfA4DPatternIsStratified) {
  for (uint32_t seed : {5u, 991u})
    for (int k = 0; k <= 12; ++k)
      for (int d = 0; d < 4; ++d) {
        std::set<int> cells;
        for (uint32_t i = 0; i < (1u << k); ++i) cells.insert(int(sobol_owen_4d(i, seed)[d] * float(1 << k)));
        EXPECT_EQ(cells.size(), size_t(1) << k) << "seed " << seed << " k " << k << " dim " << d;
      }
}

TEST(Sobol, DifferentSeedsGiveDifferentPoints) {
  int same = 0;
  for (uint32_t i = 0; i < 64; ++i) same += sobol_owen_2d(i, 1) == sobol_owen_2d(i, 2);
  EXPECT_LT(same, 2);
}

TEST(Sobol, IntegratesSmoothFunctionsBetterThanRandom) {
  // f(x, y) = x y over [0,1]^2 = 1/4. Averaged over 64 seeds, the squared error at 256 samples must be far below
  // the independent-sampling variance Var[xy] / 256 = (1/9 - 1/16) / 256.
  double sq = 0.0;
  for (uint32_t seed = 0; seed < 64; ++seed) {
    double sum = 0.0;
    for (uint32_t i = 0; i < 256; ++i) {
      vec2 p = sobol_owen_2d(i, seed * 7919u + 1u);
      sum += double(p.x) * p.y;
    }
    double e = sum / 256 - 0.25;
    sq += e * e;
  }
  double mse = sq / 64;
  double random_mse = (1.0 / 9 - 1.0 / 16) / 256;
  EXPECT_LT(mse, 0.05 * random_mse);
}

TEST(Sobol, ValuesAreInTheUnitInterval) {
  for (uint32_t i = 0; i < 100000; i += 7) {
    vec2 p = sobol_owen_2d(i, i * 31u);
    float q = sobol_owen_1d(i, i * 17u);
    ASSERT_GE(p.x, 0.0f);
    ASSERT_LT(p.x, 1.0f);
    ASSERT_GE(p.y, 0.0f);
    ASSERT_LT(p.y, 1.0f);
    ASSERT_GE(q, 0.0f);
    ASSERT_LT(q, 1.0f);
  }
}

}  // namespace
}  // namespace pt
