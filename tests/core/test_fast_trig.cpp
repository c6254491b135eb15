// The polynomial sine, cosine and arctangent of core/fast_trig.h against double precision: absolute error over the
// ranges the warps use, relative error near zero (where the spherical rectangle's small angles live), and the
// quarter split's invariants. Deterministic grids, so nothing here can flake.
#include <gtest/gtest.h>

#include <cmath>

#include "core/fast_trig.h"

namespace pt {
namespace {

// One float ulp at 1 is 1.19e-7; the Cephes polynomials are within about 1 ulp of the true value on their reduced
// ranges, and the reduction adds at most half an ulp of the argument.
constexpr double kAbsTol = 2.4e-7;

TEST(FastTrig, SinCosMatchDoublePrecision) {
  double worst_sin = 0.0, worst_cos = 0.0;
  const int n = 400000;
  for (int i = 0; i <= n; ++i) {
    const float x = -12.0f + 24.0f * float(i) / float(n);  // several turns either side of zero
    const SinCos sc = fast_sincos(x);
    worst_sin = std::max(worst_sin, std::abs(double(sc.sin) - std::sin(double(x))));
    worst_cos = std::max(worst_cos, std::abs(double(sc.cos) - std::cos(double(x))));
  }
  EXPECT_LT(worst_sin, kAbsTol);
  EXPECT_LT(worst_cos, kAbsTol);
}

TEST(FastTrig, SinCosKeepRelativePrecisionNearTheirZeros) {
  // Near x = 0 the sine must be relative-accurate (the warps take sin of small angles); the same near k pi / 2
  // for whichever of the two vanishes there, up to the reduction's absolute error of a few 1e-8.
  for (float x = 1e-30f; x < 0.5f; x *= 1.37f) {
    const SinCos sc = fast_sincos(x);
    EXPECT_NEAR(sc.sin / std::sin(double(x)), 1.0, 3e-7) << x;
    EXPECT_NEAR(fast_sincos(-x).sin / std::sin(-double(x)), 1.0, 3e-7) << x;
    EXPECT_NEAR(sc.cos, std::cos(double(x)), 1.2e-7) << x;
  }
  for (int k = -4; k <= 4; ++k) {
    for (float e = 1e-6f; e < 0.1f; e *= 3.1f) {
      const float x = float(k) * 1.5707963267948966f + e;
      const double exact_sin = std::sin(double(x)), exact_cos = std::cos(double(x));
      const SinCos sc = fast_sincos(x);
      EXPECT_NEAR(sc.sin, exact_sin, 1e-7 + 3e-7 * std::abs(exact_sin)) << x;
      EXPECT_NEAR(sc.cos, exact_cos, 1e-7 + 3e-7 * std::abs(exact_cos)) << x;
    }
  }
}

TEST(FastTrig, SplitAtan2MatchesDoubleOnTheWholeCircle) {
  double worst = 0.0;
  const int n = 720000;
  for (int i = 0; i < n; ++i) {
    const double angle = -3.14159 + 6.28318 * double(i) / double(n);
    const float r = 0.5f + float(i % 7);  // the magnitude does not matter
    const float p = r * float(std::sin(angle)), q = r * float(std::cos(angle));
    const SplitAngle a = split_atan2(p, q);
    ASSERT_LE(std::abs(a.rest), 0.7853982f + 1e-7f) << p << " " << q;
    ASSERT_LE(std::abs(a.quarter), 2);
    const double got = a.quarter * (M_PI / 2) + double(a.rest);
    double diff = got - std::atan2(double(p), double(q));
    if (diff > M_PI) diff -= 2 * M_PI;  // +-pi are the same angle
    if (diff < -M_PI) diff += 2 * M_PI;
    worst = std::max(worst, std::abs(diff));
  }
  EXPECT_LT(worst, kAbsTol);
}

TEST(FastTrig, SplitAtan2KeepsSmallRemaindersRelativeAccurate) {
  // An angle just off a quarter turn: the remainder must carry the small part to float's relative precision, or
  // the spherical rectangle's tiny solid angles (differences of such angles) lose it.
  for (float e = 1e-20f; e < 0.3f; e *= 2.3f) {
    const double t = std::tan(double(e));
    for (int quarter = -2; quarter <= 2; ++quarter) {
      // The point at angle quarter * pi/2 + e, built exactly from (1, tan e) rotated by whole quarter turns.
      float p = float(t), q = 1.0f;
      for (int k = 0; k < (quarter + 4) % 4; ++k) std::swap(p, q), q = -q;
      const SplitAngle a = split_atan2(p, q);
      EXPECT_EQ((a.quarter - quarter + 8) % 4, 0) << e << " " << quarter;  // a half turn is +2 or -2
      EXPECT_NEAR(a.rest / double(e), 1.0, 3e-7) << e << " quarter " << quarter;
    }
  }
}

}  // namespace
}  // namespace pt
