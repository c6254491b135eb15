#pragma once
/// Ray-sphere intersection with the precision improvements of Haines et al. 2019 (Ray Tracing Gems, chapter 7):
/// the discriminant comes from the squared distance of the center to the ray line, |f x d|^2 / |d|^2, and the
/// smaller root from the larger by Vieta. Evaluated in double: at a distance of 1e4 the float difference o - c is
/// already rounded by about 5e-4, which is half the radius of a 1e-3 sphere.
#include "core/ray.h"

namespace pt {

/// Nearest t in (0, tmax) where the ray meets the sphere, or +inf. Both surfaces (outside and inside) are hit;
/// hits within rounding distance of the origin are the surface the ray just left, and are skipped.
inline float intersect_sphere(const Ray& ray, vec3 center, float radius, float tmax) {
  const dvec3 f = dvec3(ray.org) - dvec3(center);
  const dvec3 d(ray.dir);
  const double a = glm::dot(d, d);
  const double b = -glm::dot(f, d);
  const dvec3 cr = glm::cross(f, d);
  const double cr2 = glm::dot(cr, cr), r2 = double(radius) * double(radius);
  // Most rays miss: they leave here without a division. The factor covers the rounding of both sides, so every
  // ray that passes the test below passes this one.
  if (!(cr2 <= r2 * a * (1.0 + 0x1p-48))) return kInfinity;
  const double line_dist2 = cr2 / a;
  if (!(line_dist2 <= r2)) return kInfinity;
  const double disc = a * (r2 - line_dist2);  // = b^2 - a c, without the cancellation
  const double ff = glm::dot(f, f), c = ff - r2;
  const double q = b + std::copysign(std::sqrt(disc), b);
  double t0, t1;
  if (q == 0.0) {
    t0 = t1 = b / a;
  } else {
    t0 = c / q;
    t1 = q / a;
  }
  if (t0 > t1) std::swap(t0, t1);
  // A root counts beyond eps = k (|f| + r) / |d|, k = 4 gamma(5). Most roots are far beyond it: t^2 a > 4 k^2
  // (|f|^2 + r^2) >= 2 k^2 (|f| + r)^2 proves t > eps with a margin of sqrt(2), far above double rounding, so the
  // two square roots and the division of eps are only taken near the origin, where they decide as before.
  constexpr double k = 4.0 * double(gamma_bound(5));
  const double far_beyond = 4.0 * k * k * (ff + r2);
  auto beyond_eps = [&](double t) {
    if (!(t > 0.0)) return false;
    if (t * t * a > far_beyond) return true;
    return t > k * (std::sqrt(ff) + radius) / std::sqrt(a);
  };
  // Compare the float distances that are returned, so that tmax = t excludes exactly that hit.
  if (beyond_eps(t0) && float(t0) < tmax) return float(t0);
  if (beyond_eps(t1) && float(t1) < tmax) return float(t1);
  return kInfinity;
}

}  // namespace pt
