// The pixel sampler (src/render/sampler.h): what the integrator and the error estimate rely on.
//  - Sobol: each half of a pixel's samples (the even and the odd indices, the film's two halves) is its own
//    scrambled sequence, so the first 2^k samples of a half form a (0, k, 2)-net in every draw;
//  - the two halves and neighbouring pixels are scrambled apart;
//  - both samplers depend only on (seed, pixel, sample index), never on the order samples are taken in.
#include <gtest/gtest.h>

#include <vector>

#include "../core/chi_square.h"
#include "net_check.h"
#include "render/sampler.h"

namespace pt {
namespace {

/// Draw `draw` (0 = the camera's) of sample `index` of `pixel`: its first two numbers.
vec2 draw_of(uint64_t seed, uint64_t pixel, uint64_t index, int draw, SamplerKind kind) {
  PixelSampler s = PixelSampler::start(seed, pixel, index, kind);
  vec2 v(0.0f);
  for (int d = 0; d <= draw; ++d) v = s.next2d();
  return v;
}

TEST(PixelSampler, EachHalfOfAPixelsSobolSamplesIsANetInEveryDraw) {
  for (uint64_t seed : {1ull, 42ull})
    for (uint64_t pixel : {0ull, 777ull, 123456ull})
      for (int draw : {0, 1, 2, 7})
        for (int half : {0, 1})
          for (int k = 0; k <= 8; ++k) {
            std::vector<vec2> pts;
            for (uint64_t j = 0; j < (1ull << k); ++j)
              pts.push_back(draw_of(seed, pixel, 2 * j + uint64_t(half), draw, SamplerKind::sobol));
            EXPECT_TRUE(test::is_net(pts, k))
                << "seed " << seed << " pixel " << pixel << " draw " << draw << " half " << half << " k " << k;
          }
}

TEST(PixelSampler, HalvesPixelsAndDrawsAreScrambledApart) {
  // The same sample of the two halves, of two neighbouring pixels and of two draws: different numbers nearly always
  // (one shared scramble would make them equal or correlated, and the halves' difference would no longer estimate
  // the error).
  int same_half = 0, same_pixel = 0, same_draw = 0;
  const int n = 256;
  for (int j = 0; j < n; ++j) {
    const vec2 a = draw_of(5, 100, 2 * uint64_t(j), 1, SamplerKind::sobol);
    same_half += a == draw_of(5, 100, 2 * uint64_t(j) + 1, 1, SamplerKind::sobol);
    same_pixel += a == draw_of(5, 101, 2 * uint64_t(j), 1, SamplerKind::sobol);
    same_draw += a == draw_of(5, 100, 2 * uint64_t(j), 2, SamplerKind::sobol);
  }
  EXPECT_LE(same_half, 2);
  EXPECT_LE(same_pixel, 2);
  EXPECT_LE(same_draw, 2);
}

TEST(PixelSampler, NumbersDependOnlyOnSeedPixelAndIndex) {
  for (SamplerKind kind : {SamplerKind::independent, SamplerKind::sobol}) {
    int repeats = 0;
    for (uint64_t i = 0; i < 64; ++i) {
      // Started twice, the same sample gives the same numbers...
      const vec2 v = draw_of(9, 3, i, 3, kind);
      EXPECT_EQ(v, draw_of(9, 3, i, 3, kind));
      // ...and the next sample, or another seed, other ones.
      repeats += v == draw_of(9, 3, i + 1, 3, kind);
      repeats += v == draw_of(10, 3, i, 3, kind);
    }
    EXPECT_LE(repeats, 2) << int(kind);
  }
}

/// Pearson's chi-square of points against the uniform density on an 8 x 8 grid of the unit square (63 degrees of
/// freedom: mean 63, and 130 has a probability near 1.5e-6).
double chi_square_8x8(const std::vector<vec2>& pts) {
  const test::ChiSquareResult r = test::chi_square_of_points(pts, [](vec2) { return 1.0; }, 8, 8);
  EXPECT_EQ(r.dof, 63) << "no cell pooled";
  return r.statistic;
}

TEST(PixelSampler, TheNumbersOfADrawAndOfTwoDrawsFillTheSquare) {
  // A pixel's samples, for both samplers: the two numbers of one draw (next2d, and the pairs of next<4>), and the
  // first numbers of two successive draws, are uniform in the unit square. Numbers repeated within or across
  // draws would put the points on a line (the diagonal); a stratification (Sobol) passes with room to spare.
  for (SamplerKind kind : {SamplerKind::independent, SamplerKind::sobol}) {
    std::vector<vec2> camera, pair01, pair23, across;
    for (uint64_t i = 0; i < 4096; ++i) {
      PixelSampler s = PixelSampler::start(11, 4242, i, kind);
      camera.push_back(s.next2d());
      float v[4];
      s.next<4>(v);
      pair01.push_back({v[0], v[1]});
      pair23.push_back({v[2], v[3]});
      across.push_back({v[0], s.next1d()});
    }
    EXPECT_LT(chi_square_8x8(camera), 130.0) << "next2d, sampler " << int(kind);
    EXPECT_LT(chi_square_8x8(pair01), 130.0) << "next<4> numbers 0 and 1, sampler " << int(kind);
    EXPECT_LT(chi_square_8x8(pair23), 130.0) << "next<4> numbers 2 and 3, sampler " << int(kind);
    EXPECT_LT(chi_square_8x8(across), 130.0) << "two draws, sampler " << int(kind);
  }
}

TEST(PixelSampler, AllNumbersAreInTheUnitInterval) {
  for (SamplerKind kind : {SamplerKind::independent, SamplerKind::sobol})
    for (uint64_t i = 0; i < 4096; ++i) {
      PixelSampler s = PixelSampler::start(3, i % 17, i, kind);
      float v[4];
      s.next<4>(v);
      for (float x : v) ASSERT_TRUE(x >= 0.0f && x < 1.0f) << x;
      ASSERT_LT(s.next1d(), 1.0f);
    }
}

}  // namespace
}  // namespace pt
