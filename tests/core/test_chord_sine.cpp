// core/chord_sine.h: the paired (SIMD) chord ends equal the scalar ones bit for bit, so the spherical rectangle
// samples the same points with either; and the scalar form keeps its exact 1 -+ sine terms against double
// precision where the chord is seen nearly end-on. Deterministic inputs, so nothing here can flake.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/chord_sine.h"

namespace pt {
namespace {

void expect_same_bits(const ChordSine& a, const ChordSine& b, float y, float d2) {
  EXPECT_EQ(std::bit_cast<uint32_t>(a.sine), std::bit_cast<uint32_t>(b.sine)) << y << " " << d2;
  EXPECT_EQ(std::bit_cast<uint32_t>(a.inv_r), std::bit_cast<uint32_t>(b.inv_r)) << y << " " << d2;
  EXPECT_EQ(std::bit_cast<uint32_t>(a.one_minus), std::bit_cast<uint32_t>(b.one_minus)) << y << " " << d2;
  EXPECT_EQ(std::bit_cast<uint32_t>(a.one_plus), std::bit_cast<uint32_t>(b.one_plus)) << y << " " << d2;
}

TEST(ChordSine, PairEqualsScalarBitForBit) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<float> mantissa(1.0f, 2.0f);
  std::uniform_int_distribution<int> exponent(-40, 40), coin(0, 1);
  std::vector<float> ys = {0.0f, -0.0f, 1e-30f, -1e-30f, 1.0f, -1.0f, 3e18f, -3e18f};
  for (int i = 0; i < 20000; ++i) ys.push_back((coin(gen) ? 1.0f : -1.0f) * std::ldexp(mantissa(gen), exponent(gen)));
  int failures = 0;
  for (size_t i = 0; i + 1 < ys.size() && failures == 0; i += 2) {
    const float d2 = std::ldexp(mantissa(gen), exponent(gen));
    ChordSine a, b;
    chord_sines(ys[i], ys[i + 1], d2, a, b);
    expect_same_bits(a, chord_sine(ys[i], d2), ys[i], d2);
    expect_same_bits(b, chord_sine(ys[i + 1], d2), ys[i + 1], d2);
    failures += ::testing::Test::HasFailure();
  }
  // y = +-0 (a receiver level with a chord end): 1 -+ 0 / r come out as d2 / r^2 and r^2 / r^2, which differ by an
  // ulp for about half of the d2, so the pair must pick its ends by y > 0 exactly as the scalar form does.
  for (int i = 0; i < 1000 && failures == 0; ++i) {
    const float d2 = std::ldexp(mantissa(gen), exponent(gen));
    ChordSine a, b;
    chord_sines(0.0f, -0.0f, d2, a, b);
    expect_same_bits(a, chord_sine(0.0f, d2), 0.0f, d2);
    expect_same_bits(b, chord_sine(-0.0f, d2), -0.0f, d2);
    failures += ::testing::Test::HasFailure();
  }
}

TEST(ChordSine, OneMinusAndOnePlusStayExactEndOn) {
  // A chord seen nearly end-on: |y| much larger than sqrt(d2), where 1 - |y| / r = d2 / (r (r + |y|)) would cancel.
  for (float y : {10.0f, -10.0f, 1e3f, -1e3f, 0.5f, -0.5f}) {
    for (float d2 : {1e-6f, 1e-3f, 0.25f, 4.0f}) {
      const ChordSine c = chord_sine(y, d2);
      const double r = std::sqrt(double(d2) + double(y) * double(y)), s = double(y) / r;
      const double small = double(d2) / (r * (r + std::abs(double(y))));  // 1 - |y| / r without cancellation
      const double one_minus = y > 0 ? small : 2.0 - small, one_plus = y > 0 ? 2.0 - small : small;
      EXPECT_NEAR(c.sine, s, 2e-7 * std::abs(s)) << y << " " << d2;
      EXPECT_NEAR(c.inv_r, 1.0 / r, 3e-7 / r) << y << " " << d2;
      EXPECT_NEAR(c.one_minus, one_minus, 4e-7 * one_minus) << y << " " << d2;
      EXPECT_NEAR(c.one_plus, one_plus, 4e-7 * one_plus) << y << " " << d2;
    }
  }
}

}  // namespace
}  // namespace pt
