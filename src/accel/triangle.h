#pragma once
/// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013, "Watertight Ray/Triangle Intersection",
/// JCGT 2(1); pbrt-v4 section 6.5.3). Rays through a shared edge or vertex hit at least one of the triangles that
/// share it, so closed meshes do not leak.
#include <algorithm>
#include <limits>

#include "core/ray.h"

namespace pt {

/// The per-ray part of the test: a permutation making z the dominant direction axis and a shear to +z.
struct WatertightRay {
  vec3 org;
  int kx, ky, kz;
  float sx, sy, sz;
};

inline WatertightRay make_watertight_ray(const Ray& ray) {
  WatertightRay w;
  w.org = ray.org;
  vec3 a = glm::abs(ray.dir);
  w.kz = max_dimension(a);
  w.kx = w.kz == 2 ? 0 : w.kz + 1;
  w.ky = w.kx == 2 ? 0 : w.kx + 1;
  // Woop et al. swap kx and ky when dir[kz] < 0 to keep the winding for back-face culling. Both sides are hit here,
  // and the swap would only negate e0, e1, e2, det and t_scaled exactly (no FMA contraction, CMakeLists.txt), so it
  // is left out: the hits, distances and barycentrics are the same bit for bit.
  w.sz = 1.0f / ray.dir[w.kz];
  w.sx = -ray.dir[w.kx] * w.sz;
  w.sy = -ray.dir[w.ky] * w.sz;
  return w;
}

/// Result of a triangle hit: distance and barycentrics (b0, b1, b2) of the hit point.
struct TriangleHit {
  float t;
  float b0, b1, b2;
};

/// Whether a hit whose float t is within its rounding bound `delta_t` of 0 is in front of the origin, decided by
/// recomputing t in double from the same float inputs (vertices, origin and the ray's shear). The hit keeps its
/// float t (at least the smallest positive float), so the scalar and the 4-lane tests still agree bit for bit. The
/// float test alone rejects such hits (pbrt-v4 section 6.8.4), which is right for the triangle a ray was spawned from,
/// but a ray leaving a surface at a grazing angle near an edge meets the neighbouring triangle a little further on,
/// where 1/det makes delta_t large: rejecting that hit let the ray pass through the closed surface (issue 13: light
/// seen from inside a closed mesh). In double the same error bound is 2^-29 of delta_t; 2^-28 leaves a margin. The
/// spawning triangle's true t is negative by the spawn offset over the cosine, far beyond that bound, so it stays
/// rejected.
inline bool small_t_is_positive(const WatertightRay& w, vec3 p0, vec3 p1, vec3 p2, float delta_t, float det_f) {
  const dvec3 o(w.org);
  const dvec3 a = dvec3(p0) - o, b = dvec3(p1) - o, c = dvec3(p2) - o;
  const double sx = w.sx, sy = w.sy, sz = w.sz;
  const double az = a[w.kz], bz = b[w.kz], cz = c[w.kz];
  const double ax = a[w.kx] + sx * az, ay = a[w.ky] + sy * az;
  const double bx = b[w.kx] + sx * bz, by = b[w.ky] + sy * bz;
  const double cx = c[w.kx] + sx * cz, cy = c[w.ky] + sy * cz;
  const double e0 = bx * cy - by * cx, e1 = cx * ay - cy * ax, e2 = ax * by - ay * bx;
  const double det = e0 + e1 + e2;
  if (det == 0.0) return false;
  const double t = (e0 * az + e1 * bz + e2 * cz) * sz / det;
  // delta_t is proportional to 1/|det_f|; the double bound to 1/|det|. A (nearly) degenerate triangle, whose float
  // det is rounding noise, gets a huge bound and stays rejected.
  const double bound = double(delta_t) * std::abs(double(det_f)) / std::abs(det) * 0x1p-28;
  return t > bound;
}

/// Tests triangle (p0, p1, p2) against the ray for t in (0, tmax). Both sides are hit.
inline bool intersect_triangle(const WatertightRay& w, float tmax, vec3 p0, vec3 p1, vec3 p2, TriangleHit& out) {
  vec3 a = p0 - w.org, b = p1 - w.org, c = p2 - w.org;
  float az = a[w.kz], bz = b[w.kz], cz = c[w.kz];
  float ax = a[w.kx] + w.sx * az, ay = a[w.ky] + w.sy * az;
  float bx = b[w.kx] + w.sx * bz, by = b[w.ky] + w.sy * bz;
  float cx = c[w.kx] + w.sx * cz, cy = c[w.ky] + w.sy * cz;
  float e0 = bx * cy - by * cx;
  float e1 = cx * ay - cy * ax;
  float e2 = ax * by - ay * bx;
  // Exactly zero edge functions are re-evaluated in double so edges are decided consistently.
  if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
    e0 = float(double(bx) * double(cy) - double(by) * double(cx));
    e1 = float(double(cx) * double(ay) - double(cy) * double(ax));
    e2 = float(double(ax) * double(by) - double(ay) * double(bx));
  }
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) return false;
  float det = e0 + e1 + e2;
  if (det == 0.0f) return false;
  az *= w.sz; bz *= w.sz; cz *= w.sz;
  float t_scaled = e0 * az + e1 * bz + e2 * cz;
  if (det < 0.0f && (t_scaled >= 0.0f || t_scaled < tmax * det)) return false;
  if (det > 0.0f && (t_scaled <= 0.0f || t_scaled > tmax * det)) return false;
  float inv_det = 1.0f / det;
  float t = t_scaled * inv_det;
  if (!(t < tmax)) return false;
  // Conservative check that t is really positive (pbrt-v4 section 6.8.4): reject hits within rounding of 0.
  float max_zt = max_component(glm::abs(vec3(az, bz, cz)));
  float delta_z = gamma_bound(3) * max_zt;
  float max_xt = max_component(glm::abs(vec3(ax, bx, cx)));
  float max_yt = max_component(glm::abs(vec3(ay, by, cy)));
  float delta_x = gamma_bound(5) * (max_xt + max_zt);
  float delta_y = gamma_bound(5) * (max_yt + max_zt);
  float delta_e = 2.0f * (gamma_bound(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
  float max_e = max_component(glm::abs(vec3(e0, e1, e2)));
  float delta_t = 3.0f * (gamma_bound(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * std::abs(inv_det);
  if (t <= delta_t) {
    if (!small_t_is_positive(w, p0, p1, p2, delta_t, det)) return false;
    t = std::max(t, std::numeric_limits<float>::denorm_min());
  }
  out = {t, e0 * inv_det, e1 * inv_det, e2 * inv_det};
  return true;
}

}  // namespace pt
