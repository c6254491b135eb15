#pragma once
/// Random numbers as values: a PCG32 generator (O'Neill 2014) and a hash to seed it per pixel sample, so images
/// never depend on which thread rendered which pixel.
#include <cstdint>

#include "core/math.h"

namespace pt {

/// PCG32 (XSH RR variant), the generator pbrt-v4 and Mitsuba use. 64-bit state plus a stream selector.
struct Pcg32 {
  uint64_t state = 0x853c49e6748fea9bULL;
  uint64_t inc = 0xda3e39cb94b95bdbULL;

  Pcg32() = default;
  Pcg32(uint64_t seed_state, uint64_t stream) { seed(seed_state, stream); }

  void seed(uint64_t seed_state, uint64_t stream) {
    state = 0u;
    inc = (stream << 1u) | 1u;
    next_u32();
    state += seed_state;
    next_u32();
  }
  uint32_t next_u32() {
    uint64_t old = state;
    state = old * 0x5851f42d4c957f2dULL + inc;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  /// Uniform in [0, 1): the top 24 bits, so every value is exactly representable and 1 is never returned.
  float next_float() { return float(next_u32() >> 8) * 0x1p-24f; }
};

/// 64-bit finalizer of MurmurHash3 / SplitMix64: decorrelates nearby integer inputs.
inline uint64_t mix_bits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ULL;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dULL;
  v ^= v >> 33;
  return v;
}

inline uint64_t hash_combine(uint64_t a, uint64_t b) {
  return mix_bits(a ^ (mix_bits(b) + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2)));
}

/// The generator for one pixel sample: a function of (seed, pixel, sample index) only.
inline Pcg32 make_sample_rng(uint64_t seed, uint64_t pixel_index, uint64_t sample_index) {
  uint64_t h = hash_combine(hash_combine(mix_bits(seed + 1), pixel_index), sample_index);
  return Pcg32(h, mix_bits(h ^ 0x2545f4914f6cdd1dULL));
}

}  // namespace pt
