#include "core/sampling.h"

#include <algorithm>
#include <numeric>

#include "core/frame.h"

namespace pt {

vec2 sample_uniform_disk_concentric(vec2 u) {
  vec2 o = 2.0f * u - vec2(1.0f);
  if (o.x == 0.0f && o.y == 0.0f) return vec2(0.0f);
  float theta, r;
  if (std::abs(o.x) > std::abs(o.y)) {
    r = o.x;
    theta = 0.25f * kPi * (o.y / o.x);
  } else {
    r = o.y;
    theta = 0.5f * kPi - 0.25f * kPi * (o.x / o.y);
  }
  return r * vec2(std::cos(theta), std::sin(theta));
}

vec3 sample_cosine_hemisphere(vec2 u) {
  vec2 d = sample_uniform_disk_concentric(u);
  return {d.x, d.y, safe_sqrt(1.0f - d.x * d.x - d.y * d.y)};
}

vec3 sample_uniform_sphere(vec2 u) {
  float z = 1.0f - 2.0f * u.x;
  float r = safe_sqrt(1.0f - z * z);
  float phi = kTwoPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

vec3 sample_uniform_cone(vec2 u, float cos_theta_max) {
  // 1 - cos(theta) is uniform in [0, 1 - cos_theta_max]; computing it directly keeps tiny cones accurate.
  float one_minus_cos_max = 1.0f - cos_theta_max;
  float one_minus_cos = u.x * one_minus_cos_max;
  float cos_theta = 1.0f - one_minus_cos;
  // sin^2 = (1 - cos)(1 + cos), exact for small angles where 1 - cos^2 cancels.
  float sin_theta = safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
  float phi = kTwoPi * u.y;
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

float uniform_cone_pdf(float cos_theta_max) {
  float one_minus = 1.0f - cos_theta_max;
  return one_minus > 0.0f ? 1.0f / (kTwoPi * one_minus) : kInfinity;
}

vec3 sample_uniform_triangle(vec2 u) {
  // Heitz 2019, "A Low-Distortion Map Between Triangle and Square".
  float b0, b1;
  if (u.x < u.y) {
    b0 = u.x / 2.0f;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2.0f;
    b0 = u.x - b1;
  }
  return {b0, b1, 1.0f - b0 - b1};
}

bool make_spherical_rectangle(vec3 ref, vec3 corner, vec3 ex, vec3 ey, SphericalRectangle& sr) {
  sr = SphericalRectangle{};
  // Double precision: the solid angle is a small difference of angles near pi, which float loses for small or
  // grazing rectangles.
  dvec3 dex(ex), dey(ey);
  double ex_len = glm::length(dex), ey_len = glm::length(dey);
  if (!(ex_len > 0.0) || !(ey_len > 0.0)) return false;
  dvec3 x = dex / ex_len, y = dey / ey_len, z = glm::cross(x, y);
  dvec3 d = dvec3(corner) - dvec3(ref);
  double z0 = glm::dot(d, z);
  if (z0 > 0.0) {  // make z point away from the rectangle plane
    z = -z;
    z0 = -z0;
  }
  if (!(z0 < 0.0)) return false;  // ref in the plane
  double x0 = glm::dot(d, x), y0 = glm::dot(d, y), x1 = x0 + ex_len, y1 = y0 + ey_len;
  // Corner vectors and the normals of the four planes through ref and each edge.
  dvec3 v00(x0, y0, z0), v01(x0, y1, z0), v10(x1, y0, z0), v11(x1, y1, z0);
  dvec3 n0 = glm::normalize(glm::cross(v00, v10));
  dvec3 n1 = glm::normalize(glm::cross(v10, v11));
  dvec3 n2 = glm::normalize(glm::cross(v11, v01));
  dvec3 n3 = glm::normalize(glm::cross(v01, v00));
  auto angle = [](double c) { return std::acos(std::clamp(c, -1.0, 1.0)); };
  double g0 = angle(-glm::dot(n0, n1)), g1 = angle(-glm::dot(n1, n2));
  double g2 = angle(-glm::dot(n2, n3)), g3 = angle(-glm::dot(n3, n0));
  double k = 2.0 * 3.14159265358979323846 - g2 - g3;
  double solid_angle = g0 + g1 - k;
  if (!(solid_angle > 0.0) || !std::isfinite(solid_angle)) return false;
  sr.o = ref;
  sr.x = vec3(x);
  sr.y = vec3(y);
  sr.z = vec3(z);
  sr.z0 = float(z0);
  sr.x0 = float(x0);
  sr.y0 = float(y0);
  sr.x1 = float(x1);
  sr.y1 = float(y1);
  sr.b0 = float(n0.z);
  sr.b1 = float(n2.z);
  sr.k = float(k);
  sr.solid_angle = float(solid_angle);
  return sr.solid_angle > 0.0f;
}

vec3 sample_spherical_rectangle(const SphericalRectangle& sr, vec2 u) {
  // Urena et al. 2013, section 4: invert the solid angle along x, then sample y uniformly in the projected chord.
  float au = u.x * sr.solid_angle + sr.k;
  float fu = (std::cos(au) * sr.b0 - sr.b1) / std::sin(au);
  float cu = std::copysign(1.0f, fu) / std::sqrt(fu * fu + sr.b0 * sr.b0);
  cu = std::clamp(cu, -kOneMinusEpsilon, kOneMinusEpsilon);
  float xu = -(cu * sr.z0) / safe_sqrt(1.0f - cu * cu);
  xu = std::clamp(xu, sr.x0, sr.x1);
  float d = std::sqrt(xu * xu + sr.z0 * sr.z0);
  float h0 = sr.y0 / std::sqrt(d * d + sr.y0 * sr.y0);
  float h1 = sr.y1 / std::sqrt(d * d + sr.y1 * sr.y1);
  float hv = h0 + u.y * (h1 - h0);
  float hv2 = hv * hv;
  float yv = hv2 < 1.0f - 1e-6f ? (hv * d) / std::sqrt(1.0f - hv2) : sr.y1;
  yv = std::clamp(yv, sr.y0, sr.y1);
  if (!std::isfinite(xu)) xu = 0.5f * (sr.x0 + sr.x1);
  return sr.o + xu * sr.x + yv * sr.y + sr.z0 * sr.z;
}

DiscreteDistribution::DiscreteDistribution(std::span<const float> weights) {
  const size_t n = weights.size();
  pmf_table.assign(n, 0.0f);
  cdf.assign(n + 1, 0.0f);
  if (n == 0) return;
  double total = 0.0;
  for (float w : weights) total += (std::isfinite(w) && w > 0.0f) ? double(w) : 0.0;
  double acc = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double w = total > 0.0 ? ((std::isfinite(weights[i]) && weights[i] > 0.0f) ? weights[i] / total : 0.0) : 1.0 / n;
    pmf_table[i] = float(w);
    acc += w;
    cdf[i + 1] = float(acc);
  }
  cdf[n] = 1.0f;
}

size_t DiscreteDistribution::sample(float u, float* pmf_out, float* u_remapped) const {
  // The last index whose cdf is <= u, skipping zero-probability buckets.
  size_t i = size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
  i = std::clamp<size_t>(i, 1, pmf_table.size()) - 1;
  while (pmf_table[i] == 0.0f && i + 1 < pmf_table.size()) ++i;
  while (pmf_table[i] == 0.0f && i > 0) --i;
  if (pmf_out) *pmf_out = pmf_table[i];
  if (u_remapped) {
    float r = pmf_table[i] > 0.0f ? (u - cdf[i]) / pmf_table[i] : 0.0f;
    *u_remapped = std::clamp(r, 0.0f, kOneMinusEpsilon);
  }
  return i;
}

}  // namespace pt
