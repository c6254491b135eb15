// The primitive tests (src/accel/triangle.h, sphere.h) against double-precision references computed from the same
// float inputs: hits where the exact ray hits, misses where it misses, t and barycentrics accurate relative to the
// geometry's size (not its distance from the origin), t in (0, tmax) only, and no bogus hits from degenerate input.
#include <gtest/gtest.h>

#include "accel/sphere.h"
#include "accel/triangle.h"
#include "core/rng.h"
#include "core/sampling.h"

namespace pt {
namespace {

vec3 rand3(Pcg32& rng) { return vec3(rng.next_float(), rng.next_float(), rng.next_float()); }
vec3 rand_dir(Pcg32& rng) { return sample_uniform_sphere(vec2(rng.next_float(), rng.next_float())); }

bool hit_triangle(const Ray& r, vec3 a, vec3 b, vec3 c, TriangleHit& th) {
  return intersect_triangle(make_watertight_ray(r), r.tmax, a, b, c, th);
}

/// Moller-Trumbore in double on the float inputs: the exact answer up to ~1e-16 relative.
struct RefTriangleHit {
  double t, b0, b1, b2;
};
RefTriangleHit reference_triangle(const Ray& r, vec3 p0, vec3 p1, vec3 p2) {
  dvec3 o(r.org), d(r.dir), e1 = dvec3(p1) - dvec3(p0), e2 = dvec3(p2) - dvec3(p0);
  dvec3 pv = glm::cross(d, e2);
  double inv = 1.0 / glm::dot(e1, pv);
  dvec3 tv = o - dvec3(p0), qv = glm::cross(tv, e1);
  double u = glm::dot(tv, pv) * inv, v = glm::dot(d, qv) * inv;
  return {glm::dot(e2, qv) * inv, 1.0 - u - v, u, v};
}

/// Largest distance from the ray origin to a vertex: the scale the watertight test's errors are relative to.
double local_scale(const Ray& r, vec3 p0, vec3 p1, vec3 p2) {
  dvec3 o(r.org);
  return std::max({glm::length(dvec3(p0) - o), glm::length(dvec3(p1) - o), glm::length(dvec3(p2) - o)});
}

struct Placement {
  float size;    ///< extent of the random triangles
  float offset;  ///< distance of the triangles (and rays) from the world origin
};

TEST(Triangle, HitsFromBothSidesWithAccurateTAndBarycentrics) {
  // Unit, tiny (1e-6) and huge-coordinate (1e6) triangles; at 1e6 the float spacing is 0.06, so size 16.
  for (Placement pl : {Placement{1.0f, 0.0f}, Placement{1e-6f, 0.0f}, Placement{1e-6f, 1e-3f},
                       Placement{16.0f, 1e6f}, Placement{1e3f, 1e6f}, Placement{1e-4f, 3.0f}}) {
    Pcg32 rng(1, 2);
    int front = 0, back = 0, tested = 0;
    for (int i = 0; i < 20000; ++i) {
      vec3 base = pl.offset * glm::normalize(rand3(rng) - 0.5f);
      vec3 p0 = base + pl.size * rand3(rng), p1 = base + pl.size * rand3(rng), p2 = base + pl.size * rand3(rng);
      dvec3 n = glm::cross(dvec3(p1) - dvec3(p0), dvec3(p2) - dvec3(p0));
      if (glm::length(n) < 0.02 * double(pl.size) * double(pl.size)) continue;  // well-shaped only
      n = glm::normalize(n);
      // Aim at an interior point (every barycentric >= 0.05), from either side, not grazing.
      vec3 b = sample_uniform_triangle(vec2(rng.next_float(), rng.next_float()));
      b = 0.05f + 0.85f * b;
      vec3 target = b.x * p0 + b.y * p1 + b.z * p2;
      vec3 dir = rand_dir(rng);
      if (std::abs(glm::dot(dvec3(dir), n)) < 0.1) continue;
      Ray ray{target - pl.size * (0.5f + 20.0f * rng.next_float()) * dir, dir, kInfinity};
      // At 1e6 the target itself is rounded by up to 0.03: whether the float ray passes inside is for the
      // reference to say; rays within 1e-3 (in barycentrics) of an edge are left to the watertight tests.
      const RefTriangleHit ref = reference_triangle(ray, p0, p1, p2);
      const double ref_min_b = std::min({ref.b0, ref.b1, ref.b2});
      TriangleHit th;
      if (ref_min_b < -1e-3) {
        ASSERT_FALSE(hit_triangle(ray, p0, p1, p2, th)) << "ray " << i << " passes outside, b " << ref_min_b;
        continue;
      }
      if (ref_min_b < 1e-3) continue;
      ++tested;
      ASSERT_TRUE(hit_triangle(ray, p0, p1, p2, th)) << "size " << pl.size << " offset " << pl.offset << " ray " << i;
      (glm::dot(dvec3(dir), n) < 0.0 ? front : back)++;
      const double scale = local_scale(ray, p0, p1, p2);
      EXPECT_NEAR(th.t, ref.t, 1e-5 * scale) << "ray " << i;
      EXPECT_GE(th.b0, 0.0f);
      EXPECT_GE(th.b1, 0.0f);
      EXPECT_GE(th.b2, 0.0f);
      EXPECT_NEAR(double(th.b0) + th.b1 + th.b2, 1.0, 1e-6);
      EXPECT_NEAR(th.b1, ref.b1, 1e-4);
      EXPECT_NEAR(th.b2, ref.b2, 1e-4);
      // o + t d against b0 p0 + b1 p1 + b2 p2, both relative to the origin so the offset does not mask errors.
      dvec3 o(ray.org);
      dvec3 from_t = double(th.t) * dvec3(ray.dir);
      dvec3 from_b = double(th.b0) * (dvec3(p0) - o) + double(th.b1) * (dvec3(p1) - o) + double(th.b2) * (dvec3(p2) - o);
      ASSERT_LE(glm::length(from_t - from_b), 1e-5 * scale) << "ray " << i;
    }
    EXPECT_GT(front, 4000) << "size " << pl.size;
    EXPECT_GT(back, 4000) << "size " << pl.size;
    EXPECT_GT(tested, 10000);
  }
}

TEST(Triangle, OnlyHitsInsideTheOpenIntervalZeroTmax) {
  Pcg32 rng(3, 4);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    vec3 p0 = rand3(rng), p1 = rand3(rng), p2 = rand3(rng);
    vec3 b = 0.05f + 0.85f * sample_uniform_triangle(vec2(rng.next_float(), rng.next_float()));
    vec3 target = b.x * p0 + b.y * p1 + b.z * p2;
    vec3 dir = rand_dir(rng);
    dvec3 n = glm::normalize(glm::cross(dvec3(p1) - dvec3(p0), dvec3(p2) - dvec3(p0)));
    if (std::abs(glm::dot(dvec3(dir), n)) < 0.1 || glm::length(glm::cross(p1 - p0, p2 - p0)) < 0.02f) continue;
    ++checked;
    TriangleHit th;
    // The triangle behind the origin (t < 0) is never hit.
    EXPECT_FALSE(hit_triangle(Ray{target + (0.01f + rng.next_float()) * dir, dir, kInfinity}, p0, p1, p2, th));
    Ray ray{target - (0.01f + rng.next_float()) * dir, dir, kInfinity};
    ASSERT_TRUE(hit_triangle(ray, p0, p1, p2, th));
    const float t = th.t;
    // tmax is exclusive: t itself is out, the next float above is in; anything below t is out.
    ray.tmax = t;
    EXPECT_FALSE(hit_triangle(ray, p0, p1, p2, th));
    ray.tmax = next_float_up(t);
    EXPECT_TRUE(hit_triangle(ray, p0, p1, p2, th));
    ray.tmax = 0.999f * t;
    EXPECT_FALSE(hit_triangle(ray, p0, p1, p2, th));
  }
  EXPECT_GT(checked, 5000);
  // Origin exactly in the plane of an axis-aligned triangle (t = 0 exactly): no hit, either direction.
  vec3 a(0, 0, 0.5f), b(1, 0, 0.5f), c(0, 1, 0.5f);
  for (int i = 0; i < 1000; ++i) {
    vec3 o(0.05f + 0.4f * rng.next_float(), 0.05f + 0.4f * rng.next_float(), 0.5f);
    vec3 dir = rand_dir(rng);
    if (dir.z == 0.0f) continue;
    TriangleHit th;
    EXPECT_FALSE(hit_triangle(Ray{o, dir, kInfinity}, a, b, c, th)) << "origin on the triangle, ray " << i;
  }
}

TEST(Triangle, RaysInThePlaneGiveNoBogusHit) {
  Pcg32 rng(5, 6);
  // Exactly in the plane: axis-aligned triangles, rays with a zero component along the normal through the interior.
  for (int i = 0; i < 20000; ++i) {
    const int k = i % 3;
    vec3 p0 = rand3(rng), p1 = rand3(rng), p2 = rand3(rng);
    p1[k] = p0[k], p2[k] = p0[k];
    vec3 target = (p0 + p1 + p2) / 3.0f;
    vec3 dir = rand_dir(rng);
    dir[k] = 0.0f;
    if (glm::length(dir) < 0.1f) continue;
    dir = glm::normalize(dir);
    TriangleHit th{};
    EXPECT_FALSE(hit_triangle(Ray{target - 2.0f * dir, dir, kInfinity}, p0, p1, p2, th)) << "ray " << i;
    EXPECT_FALSE(hit_triangle(Ray{target, dir, kInfinity}, p0, p1, p2, th)) << "ray " << i;
  }
  // Nearly in the plane (rounding puts them slightly off it): a reported hit must be a sane one.
  int reported = 0;
  for (int i = 0; i < 20000; ++i) {
    vec3 p0 = rand3(rng), p1 = rand3(rng), p2 = rand3(rng);
    vec3 dir = glm::normalize(p1 - p0);
    Ray ray{p0 - (0.5f + rng.next_float()) * (p1 - p0), dir, kInfinity};
    TriangleHit th;
    if (!hit_triangle(ray, p0, p1, p2, th)) continue;
    ++reported;
    ASSERT_TRUE(std::isfinite(th.t) && std::isfinite(th.b0) && std::isfinite(th.b1) && std::isfinite(th.b2));
    EXPECT_GT(th.t, 0.0f);
    EXPECT_NEAR(double(th.b0) + th.b1 + th.b2, 1.0, 1e-5);
    EXPECT_GE(std::min({th.b0, th.b1, th.b2}), 0.0f);
  }
  RecordProperty("grazing_hits_reported", reported);
}

TEST(Triangle, DegenerateTrianglesNeverHit) {
  Pcg32 rng(7, 8);
  for (int i = 0; i < 50000; ++i) {
    // Exactly collinear vertices: a on a 2^-10 grid, a + 2v and a + 3v with v on a 2^-3 grid (all exact floats).
    vec3 a = glm::floor((rand3(rng) * 8.0f - 4.0f) * 1024.0f) / 1024.0f;
    vec3 v = glm::floor(rand3(rng) * 16.0f - 8.0f) / 8.0f;
    vec3 b = a + 2.0f * v, c = a + 3.0f * v;
    vec3 target = a + rng.next_float() * 3.0f * v;
    float dist = i % 2 ? 0.01f + rng.next_float() : 10.0f + 1e3f * rng.next_float();
    vec3 o = target + dist * rand_dir(rng);
    Ray ray{o, glm::normalize(target - o), kInfinity};
    TriangleHit th;
    EXPECT_FALSE(hit_triangle(ray, a, b, c, th)) << "collinear, ray " << i;
    EXPECT_FALSE(hit_triangle(ray, c, a, b, th)) << "collinear, ray " << i;
    EXPECT_FALSE(hit_triangle(ray, a, a, c, th)) << "repeated vertex, ray " << i;
    EXPECT_FALSE(hit_triangle(ray, target, target, target, th)) << "a point, ray " << i;
  }
}

/// Sphere reference in double on the float ray: squared distance of the center to the line and the two roots.
struct RefSphere {
  double line_dist, t0, t1;
};
RefSphere reference_sphere(const Ray& r, vec3 center, float radius) {
  dvec3 d = glm::normalize(dvec3(r.dir)), f = dvec3(center) - dvec3(r.org);
  double tc = glm::dot(f, d), l = glm::length(f - tc * d);
  double h = std::sqrt(std::max(0.0, double(radius) * radius - l * l));
  double len = glm::length(dvec3(r.dir));
  return {l, (tc - h) / len, (tc + h) / len};
}

TEST(Sphere, HitsFromOutsideAndInsideMatchTheReference) {
  Pcg32 rng(9, 10);
  int outside = 0, inside = 0, misses = 0;
  for (int i = 0; i < 50000; ++i) {
    vec3 c = 20.0f * (rand3(rng) - 0.5f);
    float r = std::pow(10.0f, 4.0f * rng.next_float() - 2.0f);  // 1e-2 .. 1e2
    bool from_inside = i % 3 == 0;
    vec3 o = c + r * (from_inside ? 0.99f * rng.next_float() : 1.5f + 100.0f * rng.next_float()) * rand_dir(rng);
    // Aim near the center, sometimes past the rim.
    vec3 dir = glm::normalize(c + 2.5f * r * (rand3(rng) - 0.5f) - o);
    Ray ray{o, dir, kInfinity};
    const RefSphere ref = reference_sphere(ray, c, r);
    const float t = intersect_sphere(ray, c, r, kInfinity);
    const double tol = 1e-5 * (glm::length(dvec3(o) - dvec3(c)) + r);
    if (from_inside) {
      ASSERT_NEAR(t, ref.t1, tol) << "inside, ray " << i;
      ++inside;
    } else if (ref.line_dist < r * (1.0 - 1e-4)) {
      ASSERT_NEAR(t, ref.t0, tol) << "outside, ray " << i;
      ++outside;
      // Turned around, the sphere is behind the origin.
      EXPECT_EQ(intersect_sphere(Ray{o, -dir, kInfinity}, c, r, kInfinity), kInfinity);
      // tmax is exclusive.
      EXPECT_EQ(intersect_sphere(ray, c, r, t), kInfinity);
      EXPECT_EQ(intersect_sphere(ray, c, r, next_float_up(t)), t);
    } else if (ref.line_dist > r * (1.0 + 1e-4)) {
      ASSERT_EQ(t, kInfinity) << "ray " << i << " passes " << ref.line_dist / r << " radii from the center";
      ++misses;
    }
  }
  EXPECT_GT(outside, 10000);
  EXPECT_GT(inside, 10000);
  EXPECT_GT(misses, 1000);
}

TEST(Sphere, RaysSpawnedFromTheSurfaceOnlyHitTheFarSide) {
  // A surface point p = c + r n as the renderer reprojects it, spawned with a conservative bound on its rounding
  // error (both terms of the sum: |c| and |r n|; pbrt-v4 section 6.8.5): outward rays never re-hit the sphere, and
  // inward rays hit the far side (chord 2 r |cos|), not the surface they left.
  Pcg32 rng(11, 12);
  for (int i = 0; i < 50000; ++i) {
    float r = std::pow(10.0f, 6.0f * rng.next_float() - 3.0f);  // 1e-3 .. 1e3
    vec3 n = rand_dir(rng);
    // Centers anywhere, including -r n + small, which puts p near the world origin with |p| << r.
    vec3 c = i % 4 == 0 ? -r * n + 1e-3f * r * (rand3(rng) - 0.5f) : 200.0f * (rand3(rng) - 0.5f);
    vec3 p = c + r * n;
    vec3 err = gamma_bound(3) * (glm::abs(c) + glm::abs(r * n));
    vec3 dir = rand_dir(rng);
    float cos_theta = glm::dot(dir, n);
    Ray ray = spawn_ray(SurfacePoint{p, err, n}, dir);
    float t = intersect_sphere(ray, c, r, kInfinity);
    if (cos_theta > 0.0f) {
      ASSERT_EQ(t, kInfinity) << "outward ray " << i << " (cos " << cos_theta << ") re-hit the sphere at t = " << t;
    } else if (cos_theta < -0.01f) {
      ASSERT_NEAR(t, -2.0f * r * cos_theta, 1e-4 * (glm::length(c) + r)) << "inward ray " << i;
    }
  }
}

TEST(Sphere, TangentRaysAreClassifiedByTheirDistance) {
  const float kDelta = 1e-3f;
  // Exactly tangent (zero discriminant): either a grazing hit at t = 5 or a miss, never garbage.
  float t = intersect_sphere(Ray{vec3(1, 0, 5), vec3(0, 0, -1), kInfinity}, vec3(0), 1.0f, kInfinity);
  EXPECT_TRUE(t == kInfinity || std::abs(t - 5.0f) < 1e-6f) << t;
  EXPECT_EQ(intersect_sphere(Ray{vec3(1 + kDelta, 0, 5), vec3(0, 0, -1), kInfinity}, vec3(0), 1.0f, kInfinity),
            kInfinity);
  t = intersect_sphere(Ray{vec3(1 - kDelta, 0, 5), vec3(0, 0, -1), kInfinity}, vec3(0), 1.0f, kInfinity);
  EXPECT_NEAR(t, 5.0 - std::sqrt(1.0 - sqr(1.0 - double(kDelta))), 1e-5);
  // Random near-tangent rays, passing 1e-8 to 1e-3 radii inside or outside the rim: the test is decided in double,
  // so every ray that passes the center more than 1e-8 radii inside the rim hits and every ray more than 1e-8 outside
  // misses; no NaN anywhere.
  Pcg32 rng(13, 14);
  int grazing_hits = 0;
  for (int i = 0; i < 40000; ++i) {
    vec3 c = 10.0f * (rand3(rng) - 0.5f);
    float r = 0.1f + rng.next_float();
    vec3 dir = rand_dir(rng);
    vec3 side = glm::normalize(glm::cross(dir, rand_dir(rng)));
    const double rel = std::pow(10.0, -8.0 + 5.0 * rng.next_float()) * (i % 2 ? 1.0 : -1.0);
    float offset = float(r * (1.0 + rel));
    Ray ray{c + offset * side - (2.0f * r + 5.0f * rng.next_float()) * dir, dir, kInfinity};
    const RefSphere ref = reference_sphere(ray, c, r);
    t = intersect_sphere(ray, c, r, kInfinity);
    ASSERT_FALSE(std::isnan(t));
    if (ref.line_dist < r * (1.0 - 1e-8)) {
      ASSERT_NEAR(t, ref.t0, 1e-3 * r) << "ray " << i;  // t is ill-conditioned at grazing incidence
      grazing_hits += ref.line_dist > r * (1.0 - 1e-6);
    } else if (ref.line_dist > r * (1.0 + 1e-8)) {
      ASSERT_EQ(t, kInfinity) << "ray " << i;
    }
  }
  EXPECT_GT(grazing_hits, 2000);  // within 1e-6 radii of the rim: the band a too strict early exit would lose
}

TEST(Sphere, RaysLeavingTheRoundedSurfacePointWithoutAnOffsetDoNotReHitIt) {
  // The origin is the float nearest a point of the sphere, off the surface by up to half an ulp, either way; no
  // spawn offset. The root for the surface the ray leaves is then within rounding of 0, on either side, and must
  // be skipped (sphere.h: hits within k (|f| + r) / |d| of the origin): outward rays miss and inward rays hit the far
  // side. Centers within a few radii of the world origin, so that the origin's rounding is of the order of r's.
  Pcg32 rng(15, 16);
  int outward = 0, inward = 0;
  for (int i = 0; i < 50000; ++i) {
    const float r = std::pow(10.0f, 6.0f * rng.next_float() - 3.0f);  // 1e-3 .. 1e3
    const vec3 n = rand_dir(rng);
    const vec3 c = 4.0f * r * (rand3(rng) - 0.5f);
    const vec3 o = vec3(dvec3(c) + double(r) * dvec3(n));
    const vec3 dir = rand_dir(rng);
    const float cos_theta = glm::dot(dir, n);
    const float t = intersect_sphere(Ray{o, dir, kInfinity}, c, r, kInfinity);
    if (cos_theta > 0.3f) {
      ASSERT_EQ(t, kInfinity) << "outward ray " << i << " (cos " << cos_theta << ") re-hit the sphere at t = " << t;
      ++outward;
    } else if (cos_theta < -0.3f) {
      ASSERT_NEAR(t, -2.0f * r * cos_theta, 1e-4 * r) << "inward ray " << i;
      ++inward;
    }
  }
  EXPECT_GT(outward, 15000);
  EXPECT_GT(inward, 15000);
}

// REGRESSION TEST for a bug this suite found (src/accel/sphere.h): a sphere of radius 1e-3 at distance 1e4 must be
// hit by rays through its center. In float, f = o - c is already rounded by ~5e-4 = r/2 at 1e4, and
// l = f + (b / a) d cancels 1e4-sized terms, so l was off by about r: ~20% of rays passing within r/2 of the center
// missed (and ~1% of rays passing 1.1 r away hit). Evaluating f and |f x d|^2 / |d|^2 in double fixes both.
TEST(Sphere, TinySphereFarAwayIsHitThroughItsCenter) {
  // c = 1e4 normalize(1, 12, 3); the ray from the world origin along normalize(c) passes 2e-12 from the center.
  const vec3 c(0x1.92e958p+9f, 0x1.2e2f02p+13f, 0x1.2e2f02p+11f);
  const Ray ray{vec3(0.0f), vec3(0x1.4a10a8p-4f, 0x1.ef18fcp-1f, 0x1.ef18fcp-3f), kInfinity};
  ASSERT_LT(reference_sphere(ray, c, 1e-3f).line_dist, 1e-6);
  EXPECT_NEAR(intersect_sphere(ray, c, 1e-3f, kInfinity), reference_sphere(ray, c, 1e-3f).t0, 1e-4 * 1e4);
}

TEST(Sphere, TinySphereFarAwayIsHitAccurately) {
  // Radius 1e-3 at distance 1e4 in random directions from origins near the world origin, rays aimed within two
  // radii of the center. The float ray's own line distance (in double) decides: within r/2 it must hit with t
  // accurate to 1e-4 relative, beyond 1.5 r it must miss. (The textbook b^2 - c discriminant, ~1e-6 out of 1e8,
  // gets nearly every ray wrong.)
  Pcg32 rng(15, 16);
  const float r = 1e-3f;
  int hits = 0, misses = 0, wrong_hits = 0, wrong_misses = 0;
  for (int i = 0; i < 20000; ++i) {
    vec3 o = rand3(rng) - 0.5f;
    vec3 c = o + 1e4f * rand_dir(rng);
    vec3 side = glm::normalize(glm::cross(glm::normalize(c - o), rand_dir(rng)));
    vec3 aim = c + (2.0f * r * rng.next_float()) * side;
    Ray ray{o, glm::normalize(aim - o), kInfinity};
    const RefSphere ref = reference_sphere(ray, c, r);
    float t = intersect_sphere(ray, c, r, kInfinity);
    if (ref.line_dist < 0.5 * r) {
      ++hits;
      if (t == kInfinity) {
        ++wrong_misses;
      } else {
        ASSERT_GT(t, 0.0f);
        ASSERT_NEAR(t, ref.t0, 1e-4 * ref.t0) << "ray " << i;
      }
    } else if (ref.line_dist > 1.5 * r) {
      ++misses;
      wrong_hits += t != kInfinity;
    }
  }
  EXPECT_EQ(wrong_misses, 0) << "of " << hits << " rays within r/2 of the center";
  EXPECT_EQ(wrong_hits, 0) << "of " << misses << " rays beyond 1.5 r";
  EXPECT_GT(hits, 3000);
  EXPECT_GT(misses, 3000);
}

}  // namespace
}  // namespace pt
