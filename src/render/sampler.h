#pragma once
/// The source of random numbers for one pixel sample. Seeded only from (seed, pixel, sample index), so an image
/// does not depend on thread count or tile order (pbrt-v4's IndependentSampler::StartPixelSample).
#include "core/rng.h"

namespace pt {

struct PixelSampler {
  Pcg32 rng;

  static PixelSampler start(uint64_t seed, uint64_t pixel_index, uint64_t sample_index) {
    return PixelSampler{make_sample_rng(seed, pixel_index, sample_index)};
  }
  float next1d() { return std::min(rng.next_float(), kOneMinusEpsilon); }
  vec2 next2d() {
    float a = next1d();
    return {a, next1d()};
  }
};

}  // namespace pt
