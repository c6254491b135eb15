#include "render/light.h"

#include <algorithm>

#include "core/frame.h"

namespace pt {

namespace {

/// What every planar light holds: its corner, edges and emission, and the magnitude its sampled points' rounding
/// error scales with.
Light planar_light(LightKind kind, vec3 p0, vec3 e1, vec3 e2, vec3 emission) {
  Light l;
  l.kind = kind;
  l.p0 = p0;
  l.e1 = e1;
  l.e2 = e2;
  l.point_magnitude = glm::abs(p0) + glm::abs(e1) + glm::abs(e2);
  l.emission = emission;
  return l;
}

}  // namespace

Light make_rect_light(vec3 corner, vec3 edge1, vec3 edge2, vec3 emission) {
  Light l = planar_light(LightKind::rect, corner, edge1, edge2, emission);
  vec3 c = glm::cross(edge1, edge2);
  l.area = glm::length(c);
  l.n = l.area > 0.0f ? c / l.area : vec3(0, 0, 1);
  float l1 = glm::length(edge1), l2 = glm::length(edge2);
  l.rectangular = l.area > 0.0f && at_right_angle(edge1, edge2);
  if (l.rectangular) {
    l.inv_len2 = vec2(1.0f / (l1 * l1), 1.0f / (l2 * l2));
    l.rectangular = make_rectangle_frame(corner, edge1, edge2, l.rect_frame);
  }
  return l;
}

Light make_triangle_light(vec3 p0, vec3 p1, vec3 p2, vec3 emission) {
  Light l = planar_light(LightKind::triangle, p0, p1 - p0, p2 - p0, emission);
  vec3 c = glm::cross(l.e1, l.e2);
  float len = glm::length(c);
  l.area = 0.5f * len;
  l.n = len > 0.0f ? c / len : vec3(0, 0, 1);
  return l;
}

Light make_sphere_light(vec3 center, float radius, vec3 emission) {
  Light l;
  l.kind = LightKind::sphere;
  l.p0 = center;
  l.radius = radius;
  l.area = 4.0f * kPi * radius * radius;
  l.emission = emission;
  return l;
}

float light_power(const Light& light) {
  float p = luminance(light.emission) * light.area * kPi;
  return std::isfinite(p) && p > 0.0f ? p : 0.0f;
}

namespace {

/// Converts an area density at a point on the light to solid angle at the receiver: pdf_A * d^2 / |cos theta_l|.
float area_to_solid_angle(float pdf_area, float dist, float cos_light) {
  float c = std::abs(cos_light);
  if (!(c > 0.0f)) return 0.0f;
  float pdf = pdf_area * dist * dist / c;
  return std::isfinite(pdf) ? pdf : 0.0f;
}

/// Fills the geometric part of a sample at point p with normal n (planar lights).
bool finish_planar(const Light& light, vec3 ref, vec3 p, vec3 p_error, LightSample& out) {
  vec3 d = p - ref;
  float dist = glm::length(d);
  if (!(dist > 0.0f)) return false;
  out.point = {p, p_error, light.n};
  out.wi = d / dist;
  out.dist = dist;
  float cos_light = -glm::dot(out.wi, light.n);
  out.radiance = cos_light > 0.0f ? light.emission : vec3(0.0f);
  return cos_light > 0.0f;
}

/// Whether uniform area sampling of a rectangle is far from the solid-angle density at `ref`: whether the ratio of
/// its largest to smallest solid-angle density over the rectangle (its spread) is at least k. That density is
/// A cos(theta_l) / r^2 = A h / r^3 for a receiver at height h above the light's plane, so the ratio is
/// (r_max / r_min)^3, with r_max at a corner and r_min at the point of the rectangle nearest to ref. Where it is near
/// 1, area sampling already has the spherical rectangle's density (which is constant) at a tenth of its cost. It runs
/// for every light sample under LightSampling::automatic, so it is written without divisions or roots: spread >= k is
/// (r_max^2 / r_min^2)^(3/2) >= k, that is (r_max^2)^3 >= k^2 (r_min^2)^3, compared in double.
bool rect_area_density_spreads(const Light& light, vec3 ref, float k) {
  vec3 d = ref - light.p0;
  // ref's projection in the rectangle's edge coordinates (in [0, 1] over the rectangle)
  float a = glm::dot(d, light.e1) * light.inv_len2.x, b = glm::dot(d, light.e2) * light.inv_len2.y;
  vec3 n = d - std::clamp(a, 0.0f, 1.0f) * light.e1 - std::clamp(b, 0.0f, 1.0f) * light.e2;
  // The farthest corner: along each edge the far end is the one the projection is farther from.
  vec3 f = d - (a < 0.5f ? light.e1 : vec3(0.0f)) - (b < 0.5f ? light.e2 : vec3(0.0f));
  double r2_min = glm::dot(n, n), r2_max = glm::dot(f, f);
  return r2_max * r2_max * r2_max >= double(k) * double(k) * (r2_min * r2_min * r2_min);
}

/// The point of the triangle (a, a + ab, a + ac) nearest to p: the Voronoi regions of its vertices, then of its
/// edges, then the interior (Ericson, "Real-Time Collision Detection", 5.1.5).
vec3 nearest_point_on_triangle(vec3 p, vec3 a, vec3 ab, vec3 ac) {
  const vec3 ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const vec3 bp = ap - ab;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return a + ab;
  const vec3 cp = ap - ac;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return a + ac;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + (d1 / (d1 - d3)) * ab;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + (d2 / (d2 - d6)) * ac;
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f)
    return a + ab + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (ac - ab);
  const float inv = 1.0f / (va + vb + vc);
  return a + (vb * inv) * ab + (vc * inv) * ac;
}

/// The spread of a parallelogram that is not a rectangle, as triangle_area_density_spread: r_min from the nearer of
/// its two triangles' nearest points, r_max from its farthest corner. NaN when ref is on the light.
float parallelogram_area_density_spread(const Light& light, vec3 ref) {
  const vec3 diagonal = light.e1 + light.e2;
  const vec3 n0 = ref - nearest_point_on_triangle(ref, light.p0, light.e1, diagonal);
  const vec3 n1 = ref - nearest_point_on_triangle(ref, light.p0, diagonal, light.e2);
  const vec3 d0 = ref - light.p0, d1 = d0 - light.e1, d2 = d0 - light.e2, d3 = d0 - diagonal;
  const float r2_max =
      std::max(std::max(glm::dot(d0, d0), glm::dot(d1, d1)), std::max(glm::dot(d2, d2), glm::dot(d3, d3)));
  const float ratio = r2_max / std::min(glm::dot(n0, n0), glm::dot(n1, n1));
  return ratio * std::sqrt(ratio);
}

/// Whether `mode` asks for solid-angle sampling (before the usable-range check); under automatic, whether the light's
/// area-sampling density spreads by at least auto_min_spread at ref, by the test `spread_test` for its shape (a
/// template so that each shape's test is inlined into its caller, which runs once per light sample).
template <class SpreadTest>
inline bool wants_solid_angle(LightSampling mode, SpreadTest spread_test) {
  if (mode == LightSampling::area) return false;
  if (mode == LightSampling::solid_angle) return true;
  return spread_test();
}

/// For rectangular lights only (Light::rect_frame).
bool rect_solid_angle_usable(const Light& light, vec3 ref, LightSampling mode, float auto_min_spread,
                             SphericalRectangle& sr) {
  return wants_solid_angle(mode, [&] { return rect_area_density_spreads(light, ref, auto_min_spread); }) &&
         make_spherical_rectangle(ref, light.rect_frame, sr) && sr.solid_angle >= kMinSolidAngle &&
         sr.solid_angle <= kMaxSolidAngle;
}

/// The same for parallelograms that are not rectangles (two spherical triangles, core/sampling.h).
bool parallelogram_solid_angle_usable(const Light& light, vec3 ref, LightSampling mode, float auto_min_spread,
                                      SphericalParallelogram& sp) {
  // NaN spread (ref on the light): solid angle, as for triangles.
  return wants_solid_angle(mode, [&] { return !(parallelogram_area_density_spread(light, ref) < auto_min_spread); }) &&
         make_spherical_parallelogram(ref, light.p0, light.e1, light.e2, sp) && sp.solid_angle >= kMinSolidAngle &&
         sp.solid_angle <= kMaxSolidAngle;
}

/// The same choice for triangles (spherical triangles, Arvo 1995); sample_light and light_pdf both ask here.
bool tri_solid_angle_usable(const Light& light, vec3 ref, LightSampling mode, float auto_min_spread,
                            SphericalTriangle& st) {
  return wants_solid_angle(mode, [&] { return !(triangle_area_density_spread(light, ref) < auto_min_spread); }) &&
         make_spherical_triangle(ref, light.p0, light.e1, light.e2, st) && st.solid_angle >= kMinSolidAngle &&
         st.solid_angle <= kMaxSolidAngle;
}

/// A planar light can send light to `ref`: it has an area and `ref` is on its front side.
bool planar_faces(const Light& light, vec3 ref) {
  return light.area > 0.0f && !(glm::dot(ref - light.p0, light.n) <= 0.0f);
}

/// The bound on a point built from the light's corner and edges (pbrt-v4's error bounds, section 6.8): `ops`
/// rounded operations on inputs of these magnitudes.
vec3 planar_point_error(const Light& light, int ops) { return gamma_bound(ops) * light.point_magnitude; }

/// A sample `p` drawn by a spherical rectangle or triangle of the given solid angle: density 1 / solid angle.
bool finish_spherical(const Light& light, vec3 ref, vec3 p, float solid_angle, LightSample& out) {
  if (!finish_planar(light, ref, p, planar_point_error(light, 6), out)) return false;
  out.pdf = 1.0f / solid_angle;
  return true;
}

/// A sample `p` drawn uniformly by area: density 1 / area, converted to solid angle at ref.
bool finish_area(const Light& light, vec3 ref, vec3 p, LightSample& out) {
  if (!finish_planar(light, ref, p, planar_point_error(light, 4), out)) return false;
  out.pdf = area_to_solid_angle(1.0f / light.area, out.dist, glm::dot(out.wi, light.n));
  return out.pdf > 0.0f;
}

bool sample_sphere(const Light& light, vec3 ref, vec2 u, LightSample& out) {
  const vec3 c = light.p0;
  const float r = light.radius;
  vec3 to_center = c - ref;
  float d2 = glm::dot(to_center, to_center);
  if (d2 <= r * r * (1.0f + 1e-4f)) {
    // Receiver on or inside the sphere: uniform area sampling; only the inside sees the (outward) front side: none.
    return false;
  }
  // Uniform cone sampling of the visible cap, then the exact point on the sphere (pbrt-v4 Sphere::Sample).
  float d = std::sqrt(d2);
  float sin2_max = r * r / d2;
  float sin_max = std::sqrt(sin2_max);
  float cos_max = safe_sqrt(1.0f - sin2_max);
  float one_minus_cos_max = 1.0f - cos_max;
  float cos_theta = (cos_max - 1.0f) * u.x + 1.0f;
  float sin2_theta = 1.0f - cos_theta * cos_theta;
  if (sin2_max < 0.00068523f) {  // sin^2(1.5 deg): the direct formula loses precision for small cones
    sin2_theta = sin2_max * u.x;
    cos_theta = std::sqrt(1.0f - sin2_theta);
    one_minus_cos_max = sin2_max / 2.0f;
  }
  float cos_alpha = sin2_theta / sin_max + cos_theta * safe_sqrt(1.0f - sin2_theta / sin2_max);
  float sin_alpha = safe_sqrt(1.0f - cos_alpha * cos_alpha);
  float phi = u.y * kTwoPi;
  Frame frame = Frame::from_normal(to_center / d);
  vec3 n = frame.to_world(vec3(-sin_alpha * std::cos(phi), -sin_alpha * std::sin(phi), -cos_alpha));
  vec3 p = c + r * n;
  vec3 dir = p - ref;
  float dist = glm::length(dir);
  if (!(dist > 0.0f)) return false;
  out.point = {p, gamma_bound(5) * (glm::abs(c) + glm::abs(r * n)), n};
  out.wi = dir / dist;
  out.dist = dist;
  out.radiance = light.emission;
  out.pdf = 1.0f / (kTwoPi * one_minus_cos_max);
  return std::isfinite(out.pdf);
}

float sphere_pdf(const Light& light, vec3 ref) {
  vec3 to_center = light.p0 - ref;
  float d2 = glm::dot(to_center, to_center);
  float r2 = light.radius * light.radius;
  if (d2 <= r2 * (1.0f + 1e-4f)) return 0.0f;
  float sin2_max = r2 / d2;
  float one_minus_cos_max = sin2_max < 0.00068523f ? sin2_max / 2.0f : 1.0f - safe_sqrt(1.0f - sin2_max);
  return 1.0f / (kTwoPi * one_minus_cos_max);
}

}  // namespace

bool sample_light(const Light& light, vec3 ref, vec2 u, LightSampling mode, LightSample& out,
                  float auto_min_spread) {
  switch (light.kind) {
    case LightKind::rect: {
      if (!planar_faces(light, ref)) return false;
      if (light.rectangular) {
        SphericalRectangle sr;
        if (rect_solid_angle_usable(light, ref, mode, auto_min_spread, sr))
          return finish_spherical(light, ref, sample_spherical_rectangle(sr, u), sr.solid_angle, out);
      } else {
        SphericalParallelogram sp;
        if (parallelogram_solid_angle_usable(light, ref, mode, auto_min_spread, sp))
          return finish_spherical(light, ref, sample_spherical_parallelogram(sp, u), sp.solid_angle, out);
      }
      return finish_area(light, ref, light.p0 + u.x * light.e1 + u.y * light.e2, out);
    }
    case LightKind::triangle: {
      if (!planar_faces(light, ref)) return false;
      SphericalTriangle st;
      if (tri_solid_angle_usable(light, ref, mode, auto_min_spread, st))
        return finish_spherical(light, ref, sample_spherical_triangle(st, u), st.solid_angle, out);
      vec3 b = sample_uniform_triangle(u);
      return finish_area(light, ref, light.p0 + b.y * light.e1 + b.z * light.e2, out);
    }
    case LightKind::sphere:
      return sample_sphere(light, ref, u, out);
  }
  return false;
}

float light_pdf(const Light& light, vec3 ref, vec3 wi, float dist, vec3 n_light, LightSampling mode,
                float auto_min_spread) {
  switch (light.kind) {
    case LightKind::rect: {
      if (!planar_faces(light, ref)) return 0.0f;
      if (light.rectangular) {
        SphericalRectangle sr;
        if (rect_solid_angle_usable(light, ref, mode, auto_min_spread, sr)) return 1.0f / sr.solid_angle;
      } else {
        SphericalParallelogram sp;
        if (parallelogram_solid_angle_usable(light, ref, mode, auto_min_spread, sp)) return 1.0f / sp.solid_angle;
      }
      return area_to_solid_angle(1.0f / light.area, dist, glm::dot(wi, n_light));
    }
    case LightKind::triangle: {
      if (!planar_faces(light, ref)) return 0.0f;
      SphericalTriangle st;
      if (tri_solid_angle_usable(light, ref, mode, auto_min_spread, st)) return 1.0f / st.solid_angle;
      return area_to_solid_angle(1.0f / light.area, dist, glm::dot(wi, n_light));
    }
    case LightKind::sphere:
      return sphere_pdf(light, ref);
  }
  return 0.0f;
}

namespace {
/// light_below_plane's margin, relative to the magnitudes of the coordinates involved: a sampled point is off the
/// light by a few float roundings of those magnitudes (spherical samples are clamped to the rectangle or triangle
/// and rebuilt from the corner and edges), the receiver's dot(wi, n) by a few more; 1e-4 is about a thousand times
/// that, and still rejects only what lies well below the plane (a tenth of a unit in a 500-unit Cornell box).
constexpr float kBelowPlaneMargin = 1e-4f;
}  // namespace

bool light_below_plane(const Light& light, std::span<const vec3> points, vec3 n) {
  // Heights along n: the plane's lowest (through the lowest point), the light's highest point (its corner plus each
  // edge's rise where it rises; a sphere's center plus its radius).
  float plane = kInfinity;
  vec3 magnitude(0.0f);  // per axis, the largest |coordinate| of the points, for the margin
  for (vec3 p : points) {
    plane = std::min(plane, glm::dot(p, n));
    magnitude = glm::max(magnitude, glm::abs(p));
  }
  const float rise1 = glm::dot(light.e1, n), rise2 = glm::dot(light.e2, n);
  float highest = glm::dot(light.p0, n);
  switch (light.kind) {
    case LightKind::rect:  // corners p0 + {0, e1} + {0, e2}
      highest += std::max(0.0f, rise1) + std::max(0.0f, rise2);
      break;
    case LightKind::triangle:  // corners p0, p0 + e1, p0 + e2
      highest += std::max(0.0f, std::max(rise1, rise2));
      break;
    case LightKind::sphere:
      highest += light.radius;
      break;
  }
  const float scale =
      glm::dot(magnitude + glm::abs(light.p0) + glm::abs(light.e1) + glm::abs(light.e2), glm::abs(n)) + light.radius;
  return highest - plane < -kBelowPlaneMargin * scale;  // false for NaN (and for no points)
}

float triangle_area_density_spread(const Light& light, vec3 ref) {
  const vec3 n = ref - nearest_point_on_triangle(ref, light.p0, light.e1, light.e2);
  const vec3 d0 = ref - light.p0, d1 = d0 - light.e1, d2 = d0 - light.e2;
  const float r2_max = std::max(glm::dot(d0, d0), std::max(glm::dot(d1, d1), glm::dot(d2, d2)));
  const float ratio = r2_max / glm::dot(n, n);
  return ratio * std::sqrt(ratio);
}

void LightSet::finalize() {
  std::vector<float> weights(lights.size());
  for (size_t i = 0; i < lights.size(); ++i) weights[i] = light_power(lights[i]);
  power = DiscreteDistribution(weights);
}

}  // namespace pt
