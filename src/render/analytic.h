#pragma once
/// Closed-form answers the tests and benchmarks compare the renderer against.
#include <vector>

#include "core/math.h"

namespace pt {

/// Irradiance at x (unit normal n) from a planar polygon of uniform radiance L, the polygon facing x (Lambert 1760;
/// Arvo 1995, "Applications of irradiance tensors"): E = L/2 sum_i angle(v_i, v_i+1) dot(n, unit(v_i x v_i+1)).
inline double polygon_irradiance(const std::vector<dvec3>& polygon, dvec3 x, dvec3 n, double L) {
  double sum = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    dvec3 a = glm::normalize(polygon[i] - x), b = glm::normalize(polygon[(i + 1) % polygon.size()] - x);
    dvec3 c = glm::cross(a, b);
    double len = glm::length(c);
    if (len == 0.0) continue;
    sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(n, c / len);
  }
  return std::abs(0.5 * L * sum);
}

/// Irradiance at x (unit normal n) from a sphere of uniform radiance L that lies wholly above x's horizon: that of
/// a point source at its center, E = pi L (r / d)^2 cos(theta), theta the angle between n and the center.
inline double sphere_irradiance(dvec3 center, double radius, dvec3 x, dvec3 n, double L) {
  const dvec3 to_center = center - x;
  const double d = glm::length(to_center);
  return M_PI * L * (radius / d) * (radius / d) * glm::dot(n, to_center / d);
}

}  // namespace pt
