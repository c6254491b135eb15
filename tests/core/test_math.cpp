// The small helpers of core/math.h that robustness rests on: the next float up and down (ray origins are rounded
// away from surfaces with them, pbrt-v4 section 6.8.6, so they must move across zero in the right direction), the
// rounding-error bound gamma(n) (section 6.8.1), the dominant axis of the watertight test, the right-angle test that
// makes a quad light a spherical rectangle, and the Rec. 709 luminance weights.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/math.h"

namespace pt {
namespace {

constexpr float kDenormMin = std::numeric_limits<float>::denorm_min();

TEST(NextFloat, StepsToTheAdjacentFloatOnBothSidesOfZero) {
  for (float v : {-0.0f, 0.0f}) {
    EXPECT_EQ(next_float_up(v), kDenormMin) << v;
    EXPECT_EQ(next_float_down(v), -kDenormMin) << v;
  }
  EXPECT_EQ(next_float_up(-kDenormMin), -0.0f);
  EXPECT_EQ(next_float_down(kDenormMin), 0.0f);
  for (float v : {1.0f, -1.0f, 3.5e-30f, -7.25e20f, 1e-42f, std::numeric_limits<float>::max() / 2}) {
    EXPECT_EQ(next_float_up(v), std::nextafter(v, kInfinity)) << v;
    EXPECT_EQ(next_float_down(v), std::nextafter(v, -kInfinity)) << v;
  }
}

TEST(NextFloat, InfinitiesStayAndTheLargestFloatsStepToThem) {
  EXPECT_EQ(next_float_up(kInfinity), kInfinity);
  EXPECT_EQ(next_float_down(-kInfinity), -kInfinity);
  EXPECT_EQ(next_float_up(std::numeric_limits<float>::max()), kInfinity);
  EXPECT_EQ(next_float_down(std::numeric_limits<float>::lowest()), -kInfinity);
  EXPECT_EQ(next_float_up(-kInfinity), std::numeric_limits<float>::lowest());
  EXPECT_EQ(next_float_down(kInfinity), std::numeric_limits<float>::max());
}

TEST(GammaBound, IsNTimesHalfAnUlpOverOneMinusThat) {
  const double eps = std::ldexp(1.0, -24);
  for (int n : {1, 2, 3, 5, 7}) EXPECT_FLOAT_EQ(gamma_bound(n), float(n * eps / (1.0 - n * eps))) << n;
  // It bounds the relative error of n chained roundings: (1 + eps)^n - 1 <= gamma(n).
  for (int n : {1, 3, 5}) EXPECT_GE(double(gamma_bound(n)), std::pow(1.0 + eps, n) - 1.0) << n;
}

TEST(MaxDimension, NamesTheLargestComponentInEveryOrder) {
  const float values[3] = {1.0f, 2.0f, 3.0f};
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms) {
    const vec3 v(values[p[0]], values[p[1]], values[p[2]]);
    const int expected = v.x == 3.0f ? 0 : v.y == 3.0f ? 1 : 2;
    EXPECT_EQ(max_dimension(v), expected) << v.x << " " << v.y << " " << v.z;
    EXPECT_EQ(max_component(v), 3.0f);
    EXPECT_EQ(min_component(v), 1.0f);
  }
}

TEST(AtRightAngle, AcceptsRoundingAndRejectsAVisibleShear) {
  EXPECT_TRUE(at_right_angle(vec3(2, 0, 0), vec3(0, 0, 3)));
  EXPECT_TRUE(at_right_angle(vec3(1, 0, 0), vec3(1e-6f, 1, 0)));  // rounding of a rotated rectangle's edges
  EXPECT_FALSE(at_right_angle(vec3(1, 0, 0), vec3(1e-3f, 1, 0)));  // 0.06 degrees off: a parallelogram
  EXPECT_FALSE(at_right_angle(vec3(1, 0, 0), vec3(1, 1, 0)));
  // Scale-free: the same shapes 1e6 times larger or smaller answer the same.
  for (float s : {1e-6f, 1e6f}) {
    EXPECT_TRUE(at_right_angle(s * vec3(1, 0, 0), s * vec3(1e-6f, 1, 0))) << s;
    EXPECT_FALSE(at_right_angle(s * vec3(1, 0, 0), s * vec3(1e-3f, 1, 0))) << s;
  }
}

TEST(Luminance, UsesTheRec709Weights) {
  EXPECT_FLOAT_EQ(luminance(vec3(1, 0, 0)), 0.2126f);
  EXPECT_FLOAT_EQ(luminance(vec3(0, 1, 0)), 0.7152f);
  EXPECT_FLOAT_EQ(luminance(vec3(0, 0, 1)), 0.0722f);
  EXPECT_DOUBLE_EQ(luminance(dvec3(0, 1, 0)), 0.7152);
  EXPECT_DOUBLE_EQ(luminance(dvec3(1, 1, 1)), 1.0);
}

TEST(SafeMath, ClampsTheRoundingJustOutsideTheDomain) {
  EXPECT_EQ(safe_sqrt(-1e-7f), 0.0f);
  EXPECT_EQ(safe_sqrt(4.0f), 2.0f);
  EXPECT_EQ(safe_acos(1.0000001f), 0.0f);
  EXPECT_FLOAT_EQ(safe_asin(-1.0000001f), -0.5f * kPi);
}

}  // namespace
}  // namespace pt
