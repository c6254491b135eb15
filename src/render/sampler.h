#pragma once
/// The source of random numbers for one pixel sample. Seeded only from (seed, pixel, sample index), so an image
/// does not depend on thread count or tile order (pbrt-v4's StartPixelSample).
#include "core/rng.h"
#include "core/sobol.h"

namespace pt {

enum class SamplerKind : int { independent = 0, sobol = 1 };

/// independent: PCG32 per pixel sample. sobol: each successive 1D/2D draw ("dimension") of a pixel's samples is
/// its own shuffled Owen-scrambled Sobol sequence over the sample index (Burley 2020), which stratifies every
/// dimension across a pixel's samples while keeping dimensions decorrelated. The even and the odd samples of a
/// pixel are two independently scrambled sequences (index i >> 1 of scramble i & 1): randomized QMC with two
/// independent replicates, so the film's two halves (sample_in_half_a, render/film.h) are independent and their
/// difference estimates the error without the bias that stratification between the halves would cause.
struct PixelSampler {
  SamplerKind kind = SamplerKind::independent;
  Pcg32 rng;
  uint32_t pixel_seed = 0;
  uint32_t sample_index = 0;
  uint32_t dimension = 0;

  static PixelSampler start(uint64_t seed, uint64_t pixel_index, uint64_t sample_index,
                            SamplerKind kind = SamplerKind::independent) {
    PixelSampler s;
    s.kind = kind;
    if (kind == SamplerKind::independent) {
      s.rng = make_sample_rng(seed, pixel_index, sample_index);
    } else {
      s.pixel_seed = uint32_t(hash_combine(mix_bits(seed + 0x51ed27u + (sample_index & 1u)), pixel_index));
      s.sample_index = uint32_t(sample_index >> 1);
    }
    return s;
  }
  uint32_t dimension_seed() { return hash_u32(pixel_seed ^ hash_u32(dimension++ * 0x9e3779b9u + 0x632be5abu)); }
  float next1d() {
    if (kind == SamplerKind::sobol) return sobol_owen_1d(sample_index, dimension_seed());
    return std::min(rng.next_float(), kOneMinusEpsilon);
  }
  vec2 next2d() {
    if (kind == SamplerKind::sobol) return sobol_owen_2d(sample_index, dimension_seed());
    float a = std::min(rng.next_float(), kOneMinusEpsilon);
    return {a, std::min(rng.next_float(), kOneMinusEpsilon)};
  }
};

}  // namespace pt
