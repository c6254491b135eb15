#pragma once
/// The source of random numbers for one pixel sample. Seeded only from (seed, pixel, sample index), so an image
/// does not depend on thread count or tile order (pbrt-v4's StartPixelSample).
#include "core/rng.h"
#include "core/sobol.h"

namespace pt {

enum class SamplerKind : int { independent = 0, sobol = 1 };

/// The render seed's part of a Sobol pixel seed: one key for the even and one for the odd samples (the two
/// independent scrambles of PixelSampler). A function of the seed alone, so a render computes it once; hashed anew
/// at every pixel sample, as it was, it headed the dependent chain each path starts with (docs/BENCHMARKS.md,
/// fourteenth round).
struct SamplerKeys {
  uint64_t seed;  ///< the render seed itself (what the independent sampler hashes per sample)
  uint64_t key[2];
  /// Two hashes of the seed, the even key with its top bit clear and the odd one with it set, so that pixel ^ key
  /// differs for every pixel and parity (no pixel index reaches bit 63).
  explicit SamplerKeys(uint64_t render_seed)
      : seed(render_seed),
        key{mix_bits(render_seed + 0x51ed27u) & ~(1ull << 63), mix_bits(render_seed + 0x51ed28u) | (1ull << 63)} {}
};

/// independent: PCG32 per pixel sample. sobol: each successive draw (a "pattern" of 1 to 4 numbers) of a pixel's
/// samples is its own shuffled Owen-scrambled 4D Sobol pattern over the sample index (Burley 2020), which
/// stratifies the dimensions of one draw jointly across a pixel's samples while keeping draws decorrelated. The
/// integrator groups what it needs per path vertex into two 4D draws (light point + light choice + roulette;
/// direction + lobe), as Cycles does.
/// The even and the odd samples of a pixel are two independently scrambled sequences (index i >> 1 of scramble
/// i & 1): randomized QMC with two independent replicates, so the film's two halves (sample_in_half_a,
/// render/film.h) are independent and their difference estimates the error without the bias that stratification
/// between the halves would cause.
struct PixelSampler {
  SamplerKind kind = SamplerKind::independent;
  Pcg32 rng;
  uint32_t pixel_seed = 0;
  uint32_t rev_index = 0;  ///< the sample index, bit-reversed (what the Sobol tables read)
  uint32_t dimension = 0;  ///< draws so far

  static PixelSampler start(const SamplerKeys& keys, uint64_t pixel_index, uint64_t sample_index, SamplerKind kind) {
    PixelSampler s;
    s.kind = kind;
    if (kind == SamplerKind::independent) {
      s.rng = make_sample_rng(keys.seed, pixel_index, sample_index);
    } else {
      // The even and the odd samples are two independently scrambled sequences (see below).
      s.pixel_seed = uint32_t(mix_bits(pixel_index ^ keys.key[sample_index & 1u]));
      s.rev_index = reverse_bits(uint32_t(sample_index >> 1));
    }
    return s;
  }
  static PixelSampler start(uint64_t seed, uint64_t pixel_index, uint64_t sample_index,
                            SamplerKind kind = SamplerKind::independent) {
    return start(SamplerKeys(seed), pixel_index, sample_index, kind);
  }
  /// The first draw's pattern (the camera's) is seeded by the pixel seed itself, a hash already: one hash less at
  /// the head of every path. Later draws hash in their draw number.
  uint32_t pattern_seed() {
    const uint32_t d = dimension++;
    return d == 0 ? pixel_seed : hash_u32(pixel_seed ^ hash_u32(d * 0x9e3779b9u + 0x632be5abu));
  }
  float uniform() { return std::min(rng.next_float(), kOneMinusEpsilon); }
  float next1d() {
    if (kind == SamplerKind::independent) return uniform();
    float v;
    sobol_owen_pattern<1>(rev_index, pattern_seed(), &v);
    return v;
  }
  vec2 next2d() {
    if (kind == SamplerKind::independent) {
      float a = uniform();
      return {a, uniform()};
    }
    float v[2];
    sobol_owen_pattern<2>(rev_index, pattern_seed(), v);
    return {v[0], v[1]};
  }
  /// The first n (1-4) numbers of one draw, into out[0..n).
  template <int n>
  void next(float* out) {
    if (kind == SamplerKind::independent) {
      for (int k = 0; k < n; ++k) out[k] = uniform();
      return;
    }
    sobol_owen_pattern<n>(rev_index, pattern_seed(), out);
  }
};

}  // namespace pt
