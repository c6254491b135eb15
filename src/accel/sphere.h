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
  const double line_dist2 = glm::dot(cr, cr) / a;
  const double r2 = double(radius) * double(radius);
  if (!(line_dist2 <= r2)) return kInfinity;
  const double disc = a * (r2 - line_dist2);  // = b^2 - a c, without the cancellation
  const double c = glm::dot(f, f) - r2;
  const double q = b + std::copysign(std::sqrt(disc), b);
  double t0, t1;
  if (q == 0.0) {
    t0 = t1 = b / a;
  } else {
    t0 = c / q;
    t1 = q / a;
  }
  if (t0 > t1) std::swap(t0, t1);
  const double eps = 4.0 * double(gamma_bound(5)) * (std::sqrt(glm::dot(f, f)) + radius) / std::sqrt(a);
  // Compare the float distances that are returned, so that tmax = t excludes exactly that hit.
  if (t0 > eps && float(t0) < tmax) return float(t0);
  if (t1 > eps && float(t1) < tmax) return float(t1);
  return kInfinity;
}

}  // namespace pt
