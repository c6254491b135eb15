// Boxes (core/aabb.h): the empty box is the identity of extend and merge, counts as empty when inverted on any one
// axis, and has zero area (the SAH multiplies areas by counts: an infinite area would turn an empty bin or leaf into
// inf * 0 = NaN); a box with a non-finite corner becomes the empty box (finite_or_empty), which is how the builders
// keep a primitive with a NaN or infinite coordinate out of every node.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/aabb.h"

namespace pt {
namespace {

TEST(Aabb, TheDefaultBoxIsEmptyWithZeroAreaAndTheIdentityOfMerging) {
  const AABB e;
  EXPECT_TRUE(e.empty());
  EXPECT_EQ(e.half_area(), 0.0f);
  const AABB b{vec3(-1, 2, 3), vec3(4, 5, 6)};
  const AABB m = merge(e, b), m2 = merge(b, e);
  EXPECT_EQ(m.lo, b.lo);
  EXPECT_EQ(m.hi, b.hi);
  EXPECT_EQ(m2.lo, b.lo);
  EXPECT_EQ(m2.hi, b.hi);
  AABB p;
  p.extend(vec3(7, -8, 9));
  EXPECT_FALSE(p.empty());
  EXPECT_EQ(p.lo, vec3(7, -8, 9));
  EXPECT_EQ(p.hi, vec3(7, -8, 9));
  EXPECT_EQ(p.half_area(), 0.0f);
}

TEST(Aabb, IsEmptyWhenInvertedOnAnyOneAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    AABB b{vec3(0.0f), vec3(1.0f)};
    b.lo[axis] = 2.0f;
    EXPECT_TRUE(b.empty()) << axis;
    EXPECT_EQ(b.half_area(), 0.0f) << axis;
  }
  EXPECT_FALSE((AABB{vec3(0.0f), vec3(0.0f)}).empty());  // a point is a box
}

TEST(Aabb, HalfAreaCenterAndExtent) {
  const AABB b{vec3(1, 2, 3), vec3(3, 5, 7)};  // 2 x 3 x 4
  EXPECT_EQ(b.half_area(), 2.0f * 3.0f + 3.0f * 4.0f + 4.0f * 2.0f);
  EXPECT_EQ(b.extent(), vec3(2, 3, 4));
  EXPECT_EQ(b.center(), vec3(2, 3.5f, 5));
  AABB a = AABB::of_point(vec3(0.0f));
  a.extend(b);
  EXPECT_EQ(a.lo, vec3(0.0f));
  EXPECT_EQ(a.hi, vec3(3, 5, 7));
}

TEST(Aabb, ANonFiniteCornerMakesTheEmptyBox) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const AABB ok{vec3(-1.0f), vec3(1.0f)};
  const AABB kept = finite_or_empty(ok);
  EXPECT_EQ(kept.lo, ok.lo);
  EXPECT_EQ(kept.hi, ok.hi);
  for (int axis = 0; axis < 3; ++axis) {
    for (float bad : {nan, kInfinity, -kInfinity}) {
      AABB lo_bad = ok, hi_bad = ok;
      lo_bad.lo[axis] = bad;
      hi_bad.hi[axis] = bad;
      EXPECT_TRUE(finite_or_empty(lo_bad).empty()) << axis << " " << bad;
      EXPECT_TRUE(finite_or_empty(hi_bad).empty()) << axis << " " << bad;
      EXPECT_EQ(finite_or_empty(hi_bad).half_area(), 0.0f);
    }
  }
}

}  // namespace
}  // namespace pt
