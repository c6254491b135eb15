#pragma once
/// Owen-scrambled, shuffled Sobol points in 4D patterns (Burley 2020, "Practical Hash-based Owen Scrambling",
/// JCGT 9(4); the reversed-bit, table-driven form follows the idea of Cycles' sobol_burley.h, our own code).
/// A pattern is the first four Sobol dimensions over a pixel's sample index: the index is shuffled by a nested
/// uniform (Owen) scramble of its own seed, then each of the four outputs gets its own Owen scramble. Any prefix of
/// 2^k samples of a pattern is well stratified (dimensions 0 and 1 form a (0,k,2)-net), so progressive rendering
/// keeps the benefit.
///
/// Why it is fast: the Laine-Karras hash is an Owen scramble in the reversed-bit domain, and the generator
/// matrices are applied to the (shuffled) index a byte at a time from tables stored bit-reversed, so a dimension
/// costs three table loads, one hash and one bit reversal; no loop over the index bits, no data-dependent branch.
/// The four dimensions of a pattern share their table loads and run their hash, scramble and reversal in SSE lanes
/// (sobol_owen_pattern), so a 4D draw costs about what one dimension does.
/// Only bits 0-23 of the shuffled index are read: for sample indices below 2^24 its bits 24-31 depend on the
/// shuffle seed alone (the Owen scramble flips a bit by the bits above it, all zero), so they would add one
/// constant digital shift per pattern, which the Owen scramble of the output absorbs in distribution.
#include <array>
#include <cstdint>
#if defined(__SSE4_1__) && defined(__SSSE3__)
#include <immintrin.h>
#endif

#include "core/math.h"

namespace pt {

inline constexpr uint32_t reverse_bits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
  return x;
}

/// Laine and Karras 2011 hash that only propagates bits upward: a random Owen scramble in reversed bit order.
inline uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

/// Owen scrambling of a 32-bit fixed-point value in [0,1): each bit flipped by a hash of the bits above it.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

/// 32-bit integer hash (Wellons' lowbias32), to derive independent seeds.
inline uint32_t hash_u32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

namespace sobol_detail {

/// Direction numbers of one Sobol dimension (Joe and Kuo 2008 parameters: degree s, coefficients a, initial m),
/// as 32-bit fixed point: v[j] is the contribution of index bit j. Dimension 0 (s = 0) is the identity.
constexpr std::array<uint32_t, 32> direction_numbers(int s, uint32_t a, std::array<uint32_t, 3> m_init) {
  std::array<uint32_t, 32> v{};
  if (s == 0) {
    for (int j = 0; j < 32; ++j) v[size_t(j)] = 1u << (31 - j);
    return v;
  }
  std::array<uint32_t, 33> m{};  // 1-based
  for (int i = 1; i <= 32; ++i) {
    if (i <= s) {
      m[size_t(i)] = m_init[size_t(i - 1)];
      continue;
    }
    uint32_t x = m[size_t(i - s)] ^ (m[size_t(i - s)] << s);
    for (int k = 1; k < s; ++k)
      if ((a >> (s - 1 - k)) & 1u) x ^= m[size_t(i - k)] << k;
    m[size_t(i)] = x;
  }
  for (int j = 0; j < 32; ++j) v[size_t(j)] = m[size_t(j + 1)] << (31 - j);
  return v;
}

/// The first four dimensions: van der Corput, then x+1, x^2+x+1, x^3+x+1 (Joe-Kuo new-joe-kuo-6.21201, d = 2..4).
inline constexpr std::array<std::array<uint32_t, 32>, 4> kDirections = {
    direction_numbers(0, 0, {}), direction_numbers(1, 0, {1, 0, 0}), direction_numbers(2, 1, {1, 3, 0}),
    direction_numbers(3, 1, {1, 3, 1})};

/// table[slot][k][d]: the bit-reversed Sobol value of dimension d contributed by byte k of the bit-reversed
/// shuffled index, slot 0 = its top byte (index bits 0-7), 1 = bits 8-15, 2 = bits 16-23. The four dimensions of
/// one entry are adjacent, so one 16-byte load serves a whole 4D pattern.
struct Tables {
  alignas(16) uint32_t t[3][256][4];
};
constexpr Tables make_tables() {
  Tables tb{};
  for (int d = 0; d < 4; ++d)
    for (int slot = 0; slot < 3; ++slot)
      for (uint32_t k = 0; k < 256; ++k) {
        uint32_t acc = 0;
        for (int q = 0; q < 8; ++q) {
          if (!((k >> q) & 1u)) continue;
          int p = 8 * (3 - slot) + q;  // bit of the reversed index
          acc ^= reverse_bits(kDirections[size_t(d)][size_t(31 - p)]);
        }
        tb.t[slot][k][d] = acc;
      }
  return tb;
}
inline constexpr Tables kTables = make_tables();

}  // namespace sobol_detail

/// Dimension `dim` (0-3) of the unscrambled Sobol point `index`, 32-bit fixed point, by the plain definition (the
/// XOR of the direction numbers of the index's set bits). The reference the fast path is tested against.
inline uint32_t sobol_reference(uint32_t index, int dim) {
  uint32_t x = 0;
  for (int j = 0; index != 0; ++j, index >>= 1)
    if (index & 1u) x ^= sobol_detail::kDirections[size_t(dim)][size_t(j)];
  return x;
}

/// Dimension `dim` of the Sobol point whose index, bit-reversed, is `rev_index`, in the reversed-bit domain, from
/// the tables; exact for indices below 2^24 (index bits 24-31 are ignored, see the header comment).
inline uint32_t sobol_reversed(uint32_t rev_index, int dim) {
  const auto& t = sobol_detail::kTables.t;
  return t[0][rev_index >> 24][dim] ^ t[1][(rev_index >> 16) & 255u][dim] ^ t[2][(rev_index >> 8) & 255u][dim];
}

inline float fixed_to_unit_float(uint32_t x) { return std::min(float(x >> 8) * 0x1p-24f, kOneMinusEpsilon); }

namespace sobol_detail {
/// Output dimension k of a pattern is Owen-scrambled with hash_u32(seed + kDimSeedStep * (k + 1)).
inline constexpr uint32_t kDimSeedStep = 0x9e3779b9u;
}  // namespace sobol_detail

/// The first `n` (1-4) dimensions of the `index`-th point of the shuffled, scrambled 4D Sobol pattern `seed`, in
/// [0,1). `rev_index` is reverse_bits(index) (callers drawing many patterns for one sample compute it once).
/// Scalar form: the definition, and what runs without SSE4.1.
/// Dimension 0 (the radical inverse) is read from the tables like the others, not as reverse_bits(r): the two
/// differ only in reversed-domain bits 24-31, which the Laine-Karras hash never propagates downward and the 24-bit
/// float output drops, so the result is the same.
template <int n>
inline void sobol_owen_pattern_scalar(uint32_t rev_index, uint32_t seed, float* out) {
  static_assert(n >= 1 && n <= 4);
  // The shuffle: an Owen scramble of the index, kept in the reversed domain where the tables read it.
  const uint32_t r = laine_karras_permutation(rev_index, seed);
  for (int k = 0; k < n; ++k)
    out[k] = fixed_to_unit_float(reverse_bits(
        laine_karras_permutation(sobol_reversed(r, k), hash_u32(seed + sobol_detail::kDimSeedStep * uint32_t(k + 1)))));
}

#if defined(__SSE4_1__) && defined(__SSSE3__)
namespace sobol_detail {
inline __m128i mul_u32(__m128i x, uint32_t c) { return _mm_mullo_epi32(x, _mm_set1_epi32(int(c))); }
inline __m128i shr_xor(__m128i x, int s) { return _mm_xor_si128(x, _mm_srli_epi32(x, s)); }
/// Reverses the bits of each byte by two 16-entry nibble lookups (SSSE3).
inline __m128i reverse_bits_in_bytes_by_nibbles(__m128i x) {
  const __m128i low4 = _mm_set1_epi8(0x0f);
  const __m128i rev = _mm_setr_epi8(0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf);
  const __m128i rev_hi = _mm_slli_epi16(rev, 4);  // no carry crosses a byte: every entry is below 16
  __m128i lo = _mm_and_si128(x, low4), hi = _mm_and_si128(_mm_srli_epi16(x, 4), low4);
  return _mm_or_si128(_mm_shuffle_epi8(rev_hi, lo), _mm_shuffle_epi8(rev, hi));
}
/// reverse_bits on each 32-bit lane: the bytes swapped by a shuffle, the bits of each byte reversed by GFNI's
/// affine transform (one instruction) where the CPU has it, else by the nibble lookups.
inline __m128i reverse_bits4(__m128i x) {
  x = _mm_shuffle_epi8(x, _mm_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12));
#if defined(__GFNI__)
  return _mm_gf2p8affine_epi64_epi8(x, _mm_set1_epi64x(int64_t(0x8040201008040201ull)), 0);
#else
  return reverse_bits_in_bytes_by_nibbles(x);
#endif
}
}  // namespace sobol_detail

/// The same numbers as sobol_owen_pattern_scalar, the four dimensions at once in SSE lanes: one 16-byte table load
/// per index byte, and the seed hash, Owen scramble and bit reversal of all four outputs in parallel (they are
/// independent), so a 4D draw costs about what one dimension did.
template <int n>
inline void sobol_owen_pattern(uint32_t rev_index, uint32_t seed, float* out) {
  static_assert(n >= 1 && n <= 4);
  using namespace sobol_detail;
  const uint32_t r = laine_karras_permutation(rev_index, seed);
  const auto& t = kTables.t;
  __m128i v = _mm_xor_si128(_mm_load_si128(reinterpret_cast<const __m128i*>(t[0][r >> 24])),
                            _mm_xor_si128(_mm_load_si128(reinterpret_cast<const __m128i*>(t[1][(r >> 16) & 255u])),
                                          _mm_load_si128(reinterpret_cast<const __m128i*>(t[2][(r >> 8) & 255u]))));
  // Per-dimension seeds: hash_u32(seed + kDimSeedStep * (k + 1)) in each lane.
  __m128i s = _mm_add_epi32(_mm_set1_epi32(int(seed)),
                            _mm_setr_epi32(int(kDimSeedStep), int(kDimSeedStep * 2u), int(kDimSeedStep * 3u),
                                           int(kDimSeedStep * 4u)));
  s = shr_xor(mul_u32(shr_xor(mul_u32(shr_xor(s, 16), 0x7feb352du), 15), 0x846ca68bu), 16);
  // laine_karras_permutation in each lane.
  v = _mm_add_epi32(v, s);
  v = _mm_xor_si128(v, mul_u32(v, 0x6c50b47cu));
  v = _mm_xor_si128(v, mul_u32(v, 0xb82f1e52u));
  v = _mm_xor_si128(v, mul_u32(v, 0xc7afe638u));
  v = _mm_xor_si128(v, mul_u32(v, 0x8d22f6e6u));
  v = reverse_bits4(v);
  // fixed_to_unit_float: the top 24 bits, exact in float, always below 1.
  __m128 f = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srli_epi32(v, 8)), _mm_set1_ps(0x1p-24f));
  if constexpr (n == 4) {
    _mm_storeu_ps(out, f);
  } else {
    alignas(16) float tmp[4];
    _mm_store_ps(tmp, f);
    for (int k = 0; k < n; ++k) out[k] = tmp[k];
  }
}
#else
template <int n>
inline void sobol_owen_pattern(uint32_t rev_index, uint32_t seed, float* out) {
  sobol_owen_pattern_scalar<n>(rev_index, seed, out);
}
#endif

inline vec4 sobol_owen_4d(uint32_t index, uint32_t seed) {
  float v[4];
  sobol_owen_pattern<4>(reverse_bits(index), seed, v);
  return {v[0], v[1], v[2], v[3]};
}
inline vec2 sobol_owen_2d(uint32_t index, uint32_t seed) {
  float v[2];
  sobol_owen_pattern<2>(reverse_bits(index), seed, v);
  return {v[0], v[1]};
}
inline float sobol_owen_1d(uint32_t index, uint32_t seed) {
  float v;
  sobol_owen_pattern<1>(reverse_bits(index), seed, &v);
  return v;
}

}  // namespace pt
