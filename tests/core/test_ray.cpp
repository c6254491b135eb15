// Spawning rays without a magic epsilon (core/ray.h; pbrt-v4 section 6.8.6): the offset origin must lie outside the
// box of points the rounded surface point may stand for, on the side the new ray leaves to, at any scale and
// distance from the origin. Checked here in double against that box directly, for random planes and directions, so
// the property does not depend on a scene happening to show a self-intersection.
#include <gtest/gtest.h>

#include <cmath>

#include "core/ray.h"
#include "core/rng.h"
#include "core/sampling.h"

namespace pt {
namespace {

/// How far `q` lies past the error box around `p` along the normal n, on the side `side` (+1 or -1), in double:
/// positive when q is beyond every point of the box.
double clearance(dvec3 q, vec3 p, vec3 p_error, vec3 n, float side) {
  const dvec3 dn(n);
  const double along = glm::dot(q - dvec3(p), dn) * double(side);
  return along - glm::dot(glm::abs(dn), dvec3(p_error));
}

struct RandomPoint {
  SurfacePoint sp;
  vec3 w;  // a direction to leave to
};

/// A point at distance about `scale` from the origin with a position error of a few rounding steps of each
/// coordinate (as a barycentric interpolation leaves), a random unit normal, and a random direction.
RandomPoint random_point(Pcg32& rng, float scale) {
  RandomPoint r;
  r.sp.p = scale * (2.0f * vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 1.0f);
  r.sp.p_error = gamma_bound(7) * glm::abs(r.sp.p);
  r.sp.ng = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
  r.w = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
  return r;
}

TEST(OffsetRayOrigin, LeavesTheErrorBoxOnTheSideTheRayGoesTo) {
  Pcg32 rng(3, 1);
  for (float scale : {1e-3f, 1.0f, 1e3f, 1e6f}) {
    for (int i = 0; i < 20000; ++i) {
      const RandomPoint r = random_point(rng, scale);
      const float side = glm::dot(r.w, r.sp.ng) < 0.0f ? -1.0f : 1.0f;
      const vec3 o = spawn_ray(r.sp, r.w).org;
      ASSERT_GE(clearance(dvec3(o), r.sp.p, r.sp.p_error, r.sp.ng, side), 0.0)
          << "scale " << scale << " case " << i << " side " << side;
    }
  }
}

TEST(OffsetRayOrigin, MovesOffAPointWhoseErrorIsBelowItsUlp) {
  // Far from the origin the error bound can be smaller than the spacing of floats: adding it rounds back to the
  // point itself, and only the final step to the next float moves the origin off the surface.
  const vec3 p(3.0f, -2.0f, 1e5f), err(0.0f, 0.0f, 1e-4f);
  for (float nz : {1.0f, -1.0f}) {
    const vec3 n(0.0f, 0.0f, nz);
    EXPECT_GT(offset_ray_origin(p, err, n, vec3(0, 0, 1)).z, p.z) << nz;
    EXPECT_LT(offset_ray_origin(p, err, n, vec3(0, 0, -1)).z, p.z) << nz;
  }
  // With no error at all the origin stays where it is: nothing to leave.
  EXPECT_EQ(offset_ray_origin(p, vec3(0.0f), vec3(0, 0, 1), vec3(0, 0, 1)), p);
}

TEST(SpawnRayTo, StopsOutsideTheTargetsErrorBoxAndStartsOutsideItsOwn) {
  Pcg32 rng(5, 2);
  for (float scale : {1e-2f, 1.0f, 1e4f}) {
    for (int i = 0; i < 20000; ++i) {
      const RandomPoint a = random_point(rng, scale), b = random_point(rng, scale);
      const Ray ray = spawn_ray_to(a.sp, b.sp);
      ASSERT_NEAR(glm::length(ray.dir), 1.0f, 1e-6f);
      // Where the ray stops, in double: the point the traversal's t < tmax compares against (a float sum here
      // would add rounding of its own).
      const dvec3 end = dvec3(ray.org) + double(ray.tmax) * dvec3(ray.dir);
      // Sides as seen from each end: the ray leaves a toward b and arrives at b from a's side.
      const float side_a = glm::dot(b.sp.p - a.sp.p, a.sp.ng) < 0.0f ? -1.0f : 1.0f;
      const float side_b = glm::dot(ray.org - b.sp.p, b.sp.ng) < 0.0f ? -1.0f : 1.0f;
      ASSERT_GE(clearance(dvec3(ray.org), a.sp.p, a.sp.p_error, a.sp.ng, side_a), 0.0) << "scale " << scale << " " << i;
      ASSERT_GT(clearance(end, b.sp.p, b.sp.p_error, b.sp.ng, side_b), 0.0) << "scale " << scale << " " << i;
    }
  }
}

TEST(SpawnRayTo, APointToItselfGivesAnEmptyRay) {
  SurfacePoint sp;
  sp.p = vec3(1, 2, 3);
  const Ray r = spawn_ray_to(sp, sp);
  EXPECT_EQ(r.tmax, 0.0f);
  EXPECT_EQ(r.dir, sp.ng);
}

}  // namespace
}  // namespace pt
