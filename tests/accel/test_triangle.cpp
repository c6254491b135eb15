// Details of the triangle and sphere tests.
#include <gtest/gtest.h>

#include "accel/sphere.h"
#include "accel/triangle.h"

namespace pt {
namespace {

bool hit(const Ray& r, vec3 a, vec3 b, vec3 c, TriangleHit& th) {
  return intersect_triangle(make_watertight_ray(r), r.tmax, a, b, c, th);
}

TEST(Triangle, BothSidesHitAndBarycentricsReconstructThePoint) {
  vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  TriangleHit th;
  for (float dz : {-1.0f, 1.0f}) {
    Ray r{vec3(0.2f, 0.3f, -2.0f * dz), vec3(0, 0, dz), kInfinity};
    ASSERT_TRUE(hit(r, a, b, c, th));
    EXPECT_NEAR(th.t, 2.0f, 1e-6f);
    EXPECT_NEAR(th.b0 + th.b1 + th.b2, 1.0f, 1e-6f);
    vec3 p = th.b0 * a + th.b1 * b + th.b2 * c;
    EXPECT_NEAR(p.x, 0.2f, 1e-6f);
    EXPECT_NEAR(p.y, 0.3f, 1e-6f);
  }
}

TEST(Triangle, RejectsBehindInPlaneAndDegenerate) {
  vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  TriangleHit th;
  EXPECT_FALSE(hit(Ray{vec3(0.2f, 0.2f, 1), vec3(0, 0, 1), kInfinity}, a, b, c, th));   // behind
  EXPECT_FALSE(hit(Ray{vec3(0.2f, 0.2f, 1), vec3(0, 0, -1), 0.5f}, a, b, c, th));       // beyond tmax
  EXPECT_FALSE(hit(Ray{vec3(-1, 0.2f, 0), vec3(1, 0, 0), kInfinity}, a, b, c, th));     // in the plane
  EXPECT_FALSE(hit(Ray{vec3(0.5f, 0, 1), vec3(0, 0, -1), kInfinity}, a, b, vec3(2, 0, 0), th));  // collinear
  EXPECT_FALSE(hit(Ray{vec3(0, 0, 1), vec3(0, 0, -1), kInfinity}, a, a, a, th));        // a point
}

TEST(Triangle, HugeAndTinyCoordinates) {
  TriangleHit th;
  vec3 o(1e6f, 1e6f, 0);
  ASSERT_TRUE(hit(Ray{o + vec3(0.25f, 0.25f, 10), vec3(0, 0, -1), kInfinity}, o, o + vec3(1, 0, 0), o + vec3(0, 1, 0), th));
  EXPECT_NEAR(th.t, 10.0f, 1e-3f);
  vec3 s(1e-6f, 0, 0);
  ASSERT_TRUE(hit(Ray{vec3(2.5e-7f, 2.5e-7f, 1e-6f), vec3(0, 0, -1), kInfinity}, vec3(0), s, vec3(0, 1e-6f, 0), th));
  EXPECT_NEAR(th.t, 1e-6f, 1e-12f);
}

TEST(Sphere, OutsideInsideTangentAndFar) {
  EXPECT_NEAR(intersect_sphere(Ray{vec3(0, 0, 5), vec3(0, 0, -1), kInfinity}, vec3(0), 1.0f, kInfinity), 4.0f, 1e-6f);
  EXPECT_NEAR(intersect_sphere(Ray{vec3(0, 0, 0.5f), vec3(0, 0, -1), kInfinity}, vec3(0), 1.0f, kInfinity), 1.5f, 1e-6f);
  EXPECT_EQ(intersect_sphere(Ray{vec3(0, 0, 5), vec3(0, 0, 1), kInfinity}, vec3(0), 1.0f, kInfinity), kInfinity);
  EXPECT_EQ(intersect_sphere(Ray{vec3(0, 1.001f, 5), vec3(0, 0, -1), kInfinity}, vec3(0), 1.0f, kInfinity), kInfinity);
  float t = intersect_sphere(Ray{vec3(0, 0, 1e4f), vec3(0, 0, -1), kInfinity}, vec3(0), 1e-3f, kInfinity);
  EXPECT_NEAR(t, 1e4f - 1e-3f, 1e-4f * 1e4f);
  EXPECT_GT(t, 0.0f);
}

}  // namespace
}  // namespace pt
