#pragma once
/// Ray-sphere intersection with the precision improvements of Haines et al. 2019 (Ray Tracing Gems, chapter 7):
/// the discriminant is formed from the squared distance of the center to the ray line, and the smaller root from
/// the larger by Vieta, so hits stay accurate for spheres small or far relative to the ray origin.
#include "core/ray.h"

namespace pt {

/// Nearest t in (t_min_exclusive, tmax) where the ray meets the sphere, or +inf. Both surfaces (outside and
/// inside) are hit. `eps_t` rejects hits too close to the origin to be distinguished from it.
inline float intersect_sphere(const Ray& ray, vec3 center, float radius, float tmax) {
  vec3 f = ray.org - center;
  float a = glm::dot(ray.dir, ray.dir);
  float b = -glm::dot(f, ray.dir);  // half of -B
  vec3 l = f + (b / a) * ray.dir;     // vector from center to the closest point on the line
  float r2 = radius * radius;
  float disc = a * (r2 - glm::dot(l, l));
  if (disc < 0.0f) return kInfinity;
  float c = glm::dot(f, f) - r2;
  float q = b + std::copysign(std::sqrt(disc), b);
  float t0, t1;
  if (q == 0.0f) {
    t0 = t1 = b / a;
  } else {
    t0 = c / q;
    t1 = q / a;
  }
  if (t0 > t1) std::swap(t0, t1);
  // A hit closer than the rounding error of the origin's distance to the surface is the surface we left.
  float eps = 4.0f * gamma_bound(5) * (glm::length(f) + radius) / std::sqrt(a);
  if (t0 > eps && t0 < tmax) return t0;
  if (t1 > eps && t1 < tmax) return t1;
  return kInfinity;
}

}  // namespace pt
