#pragma once
/// Rays and robust spawning of secondary rays.
#include "core/math.h"

namespace pt {

/// A ray o + t d for t in [0, tmax). `dir` need not be normalized for intersection, but the integrator keeps it so.
struct Ray {
  vec3 org{0.0f};
  vec3 dir{0.0f, 0.0f, 1.0f};
  float tmax = kInfinity;
};

/// Pushes a surface point off the surface along the geometric normal by its conservative rounding-error bound
/// `p_error` (per axis), to the side `w` points to, then rounds away once more. pbrt-v4 section 6.8.6: no magic
/// epsilon, so it holds at any scale and any distance from the origin.
inline vec3 offset_ray_origin(vec3 p, vec3 p_error, vec3 n, vec3 w) {
  float d = glm::dot(glm::abs(n), p_error);
  vec3 offset = d * n;
  if (glm::dot(w, n) < 0.0f) offset = -offset;
  vec3 po = p + offset;
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0.0f) po[i] = next_float_up(po[i]);
    else if (offset[i] < 0.0f) po[i] = next_float_down(po[i]);
  }
  return po;
}

/// A point on a surface with the bound on its position error, enough to spawn rays from it robustly.
struct SurfacePoint {
  vec3 p{0.0f};
  vec3 p_error{0.0f};
  vec3 ng{0.0f, 0.0f, 1.0f};  ///< geometric normal, unit length
};

inline Ray spawn_ray(const SurfacePoint& sp, vec3 dir) {
  return Ray{offset_ray_origin(sp.p, sp.p_error, sp.ng, dir), dir, kInfinity};
}

/// A ray from `from` to `to` that stops just short of `to` (both ends offset), for shadow tests. The far end is
/// offset by to's error bound plus gamma(4) of the distance: the normalized direction is off by a few rounding
/// steps, which moves the point o + tmax dir up to that far from t. Without it, a ray reaching `to` at a grazing
/// angle could stop inside to's error box, where its own surface may lie (tests/core/test_ray.cpp).
inline Ray spawn_ray_to(const SurfacePoint& from, const SurfacePoint& to) {
  vec3 o = offset_ray_origin(from.p, from.p_error, from.ng, to.p - from.p);
  const vec3 direction_error(gamma_bound(4) * glm::length(to.p - o));
  vec3 t = offset_ray_origin(to.p, to.p_error + direction_error, to.ng, o - to.p);
  vec3 d = t - o;
  float len = glm::length(d);
  if (!(len > 0.0f)) return Ray{o, from.ng, 0.0f};
  return Ray{o, d / len, len * (1.0f - 1e-6f)};
}

}  // namespace pt
