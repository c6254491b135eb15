// A ray that leaves a closed surface at a grazing angle near an edge meets the neighbouring triangle a short way
// on, where the triangle test's rounding bound on t (pbrt-v4 section 6.8.4) is large because det is small. The
// float test alone rejected that hit as "maybe behind the origin" and the ray passed through the surface: from
// inside a closed torus-knot tube, 1 path in ~10^5 escaped to the background (issue 13). Such hits are now decided
// in double (small_t_is_positive); the triangle a ray was spawned from must still never be hit.
#include <gtest/gtest.h>

#include "accel/bvh8.h"
#include "accel/triangle.h"

namespace pt {
namespace {

// Recorded from the leak: a bounce ray spawned on a wall of the tube, and the next ring's triangle it crosses at
// t = 1.49e-3 (double-precision Moller-Trumbore: u 0.931, v 0.047), which the float test rejected.
const vec3 kOrg(0x1.549164p+1f, 0x1.a49714p-2f, -0x1.68d736p-2f);
const vec3 kDir(-0x1.85e17cp-1f, 0x1.3d8b8ep-1f, 0x1.81c9fap-3f);
const vec3 kV0(0x1.6c686p+1f, 0x1.a6e60ap-2f, -0x1.4349b2p-2f);
const vec3 kV1(0x1.53e854p+1f, 0x1.a49624p-2f, -0x1.69d9dep-2f);
const vec3 kV2(0x1.5373a8p+1f, 0x1.b78b1cp-2f, -0x1.604de6p-2f);

TEST(WatertightGrazing, TheNeighbourAGrazingRayCrossesIsHit) {
  WatertightRay w = make_watertight_ray(Ray{kOrg, kDir, kInfinity});
  TriangleHit hit;
  ASSERT_TRUE(intersect_triangle(w, kInfinity, kV0, kV1, kV2, hit));
  EXPECT_NEAR(hit.t, 1.4896e-3f, 1e-6f);
  // The 4-lane block test agrees bit for bit.
  Tri4 block{};
  for (int lane = 0; lane < 4; ++lane) set_lane(block, lane, kV0, kV1, kV2);
  block.prim[0] = 7;
  block.prim[1] = block.prim[2] = block.prim[3] = kInvalidPrim;
  Tri4Hit h4 = intersect_tri4(block, w, kInfinity);
  ASSERT_EQ(h4.lane, 0);
  EXPECT_EQ(h4.t, hit.t);
  EXPECT_TRUE(occluded_tri4(block, w, kInfinity));
}

TEST(WatertightGrazing, TheSpawningTriangleIsNeverHit) {
  // Points on a triangle, pushed off it by their rounding-error bound (as the integrator does), then rays at
  // grazing angles down to 1e-6 rad away from it: not one may hit the triangle it left.
  const vec3 a(2.7f, 0.41f, -0.35f), b(2.66f, 0.45f, -0.3f), c(2.62f, 0.39f, -0.38f);
  const vec3 n = glm::normalize(glm::cross(b - a, c - a));
  const vec3 along = glm::normalize(b - a);
  int hits = 0, tested = 0;
  for (int i = 1; i < 40; ++i)
    for (int j = 1; j < 40 - i; ++j) {
      float b1 = i / 40.0f, b2 = j / 40.0f, b0 = 1.0f - b1 - b2;
      vec3 p = b0 * a + b1 * b + b2 * c;
      vec3 err = gamma_bound(7) * (glm::abs(b0 * a) + glm::abs(b1 * b) + glm::abs(b2 * c));
      for (float side : {1.0f, -1.0f})
        for (float angle : {1e-6f, 1e-4f, 1e-2f, 0.3f}) {
          vec3 dir = glm::normalize(along + side * angle * n);
          Ray r = spawn_ray(SurfacePoint{p, err, n}, dir);
          TriangleHit hit;
          hits += intersect_triangle(make_watertight_ray(r), kInfinity, a, b, c, hit);
          ++tested;
        }
    }
  EXPECT_EQ(hits, 0) << "of " << tested;
}

}  // namespace
}  // namespace pt
