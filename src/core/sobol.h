#pragma once
/// Owen-scrambled, shuffled Sobol points (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)).
/// Every 2D draw of a path uses the first two Sobol dimensions, with its own hash-based nested uniform scramble
/// of the index (a progressive shuffle: each power-of-two prefix stays a stratified set) and of the output bits.
/// Any prefix of 2^k samples of a pixel is well stratified, so progressive rendering keeps the benefit.
#include <cstdint>

#include "core/math.h"

namespace pt {

inline uint32_t reverse_bits(uint32_t x) {
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

/// Dimensions 0 and 1 of the Sobol sequence as 32-bit fixed point.
inline void sobol_2d(uint32_t index, uint32_t& x, uint32_t& y) {
  x = reverse_bits(index);
  y = 0;
  for (uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1)
    if (index & 1u) y ^= v;
}

inline float fixed_to_unit_float(uint32_t x) { return std::min(float(x >> 8) * 0x1p-24f, kOneMinusEpsilon); }

/// The `index`-th point of the shuffled, scrambled 2D Sobol sequence identified by `seed`, in [0,1)^2.
inline vec2 sobol_owen_2d(uint32_t index, uint32_t seed) {
  uint32_t shuffled = nested_uniform_scramble(index, seed);
  uint32_t x, y;
  sobol_2d(shuffled, x, y);
  uint32_t s = hash_u32(seed ^ 0x9e3779b9u);
  return {fixed_to_unit_float(nested_uniform_scramble(x, s)),
          fixed_to_unit_float(nested_uniform_scramble(y, hash_u32(s + 1u)))};
}

/// One dimension: the shuffled, scrambled van der Corput sequence.
inline float sobol_owen_1d(uint32_t index, uint32_t seed) {
  uint32_t shuffled = nested_uniform_scramble(index, seed);
  return fixed_to_unit_float(nested_uniform_scramble(reverse_bits(shuffled), hash_u32(seed ^ 0x85ebca6bu)));
}

}  // namespace pt
