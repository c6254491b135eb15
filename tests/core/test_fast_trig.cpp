// The polynomial arctangent of core/fast_trig.h against double precision: absolute error over the whole circle,
// relative error of small remainders (where the spherical rectangle's small solid angles live), and the quarter
// split's invariants. Deterministic grids, so nothing here can flake.
#include <gtest/gtest.h>

#include <cmath>

#include "core/fast_trig.h"

namespace pt {
namespace {

// One float ulp at 1 is 1.19e-7; the Cephes polynomial is within about 1 ulp on its reduced range, and the
// reduction (x - 1) / (x + 1) and the pi/4 offset add about one more.
constexpr double kAbsTol = 2.4e-7;

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

TEST(FastTrig, SincosQuarterMatchesDouble) {
  // Over the whole quarter range: absolute error about 1 ulp of 1, and sine's relative error for small angles (the
  // concentric map's samples near the square's diagonals and axes).
  double worst_abs = 0.0, worst_rel = 0.0;
  const int n = 400000;
  for (int i = 0; i <= n; ++i) {
    const float x = float(-M_PI / 4 + (M_PI / 2) * double(i) / double(n));
    float s, c;
    fast_sincos_quarter(x, s, c);
    worst_abs = std::max({worst_abs, std::abs(s - std::sin(double(x))), std::abs(c - std::cos(double(x)))});
    if (x != 0.0f) worst_rel = std::max(worst_rel, std::abs(s / std::sin(double(x)) - 1.0));
  }
  EXPECT_LT(worst_abs, 1.2e-7);
  EXPECT_LT(worst_rel, 2.5e-7);
  for (float x = 1e-30f; x < 0.1f; x *= 3.1f) {
    float s, c;
    fast_sincos_quarter(-x, s, c);
    EXPECT_NEAR(s / -std::sin(double(x)), 1.0, 2.5e-7) << x;  // s = sin(-x)
    EXPECT_LE(c, 1.0f);
  }
}

}  // namespace
}  // namespace pt
