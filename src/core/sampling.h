#pragma once
/// Sampling warps. Each takes its uniform random numbers as arguments (Mitsuba 3 style), comes with its pdf, and is
/// chi-square tested in tests/core/test_sampling.cpp. References: pbrt-v4 section A.5 and util/sampling.h.
#include <span>
#include <vector>

#include "core/fast_trig.h"
#include "core/math.h"

namespace pt {

/// Shirley and Chiu's concentric map of the square to the disk; `radius` is the point's signed distance from the
/// center. The square's point (a, b) with |a| >= |b| goes to radius a at angle phi = pi/4 (b / a); with |b| > |a|,
/// to radius b at angle pi/2 - phi, phi = pi/4 (a / b), whose cosine and sine are phi's sine and cosine. So one
/// division and the sine and cosine of an angle within [-pi/4, pi/4] (a polynomial, no reduction) serve both
/// halves, selected without a branch: which half a sample falls in is a coin toss, so a branch on it would
/// mispredict about half the time (the branchless map with the polynomial: 10.2% -> 4.9% of a cornell36 frame
/// together; the two parts were not measured apart). Inline, as the cosine-weighted bounce below: out of line it
/// was a call on every path vertex.
inline vec2 concentric_map(vec2 u, float& radius) {
  const vec2 o = 2.0f * u - vec2(1.0f);
  const bool x_major = std::abs(o.x) > std::abs(o.y);
  const float r = x_major ? o.x : o.y, other = x_major ? o.y : o.x;
  radius = r;
  if (r == 0.0f) return vec2(0.0f);  // the center (then other is 0 too)
  float s, c;
  fast_sincos_quarter(0.25f * kPi * (other / r), s, c);
  return r * vec2(x_major ? c : s, x_major ? s : c);
}

/// Concentric map of [0,1)^2 to the unit disk (Shirley and Chiu 1997): area preserving, low distortion.
vec2 sample_uniform_disk_concentric(vec2 u);

/// Cosine-weighted direction on the hemisphere around +z (Malley's method). pdf = cos(theta) / pi.
/// cos(theta) = sqrt(1 - r^2) is taken from the disk radius, not from the point's coordinates: it does not wait for
/// the division and the polynomial, and (1 - r)(1 + r) keeps its precision near the rim.
inline vec3 sample_cosine_hemisphere(vec2 u) {
  float r;
  const vec2 d = concentric_map(u, r);
  return {d.x, d.y, safe_sqrt((1.0f - r) * (1.0f + r))};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return std::max(cos_theta, 0.0f) * kInvPi; }

/// Uniform direction on the unit sphere. pdf = 1 / (4 pi). Not used by the renderer (sphere lights sample their
/// visible cone in render/light.cpp): the random directions of the accelerator tests and benchmarks.
vec3 sample_uniform_sphere(vec2 u);
inline float uniform_sphere_pdf() { return 1.0f / (4.0f * kPi); }

/// Uniform point on a triangle as barycentrics (b0, b1, b2), b0 + b1 + b2 = 1 (the warp of Heitz 2019 used by
/// pbrt-v4). The point is b0 p0 + b1 p1 + b2 p2; pdf = 1 / area.
vec3 sample_uniform_triangle(vec2 u);

/// The solid angle subtended by the rectangle {corner + a ex + b ey : a, b in [0,1]} (ex orthogonal to ey) at `ref`,
/// with what is needed to sample it uniformly in solid angle (Urena, Fajardo and King 2013, "An Area-Preserving
/// Parametrization for Spherical Rectangles").
struct SphericalRectangle {
  vec3 o{0.0f}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};  ///< local frame at ref, z toward the rectangle plane
  float z0 = 0, x0 = 0, y0 = 0, x1 = 0, y1 = 0;       ///< rectangle bounds in that frame
  float b0 = 0, b0p = 0, b1 = 0;                    ///< b0p = sqrt(1 - b0^2), computed without cancellation
  float k = 0;          ///< Urena et al.'s k is pi - q pi/2 - k for an integer q in -2..2 (the quarters)
  bool odd_quarters = false;  ///< q odd
  float quarter_sign = 1;     ///< +1 for q = 0 or 1, -1 for q = -1, 2 or -2
  float even_sum = 0;         ///< q even: b1 + b0 (q = 0) or -(b1 + b0) (q = +-2), from the exact 1 -+ b terms
  float solid_angle = 0;                            ///< steradians; 0 if degenerate (ref in the plane, ...)
};
/// The part of a spherical rectangle that does not depend on the receiver: the corner, the unit edge directions x
/// and y (orthogonal), z = x cross y and the side lengths. Lights compute it once (render/light.cpp), so the
/// per-sample setup has no normalisation left.
struct RectangleFrame {
  vec3 corner{0.0f}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  float len_x = 0, len_y = 0;
};
/// Returns false (and len_x 0) for an edge of zero or non-finite length.
bool make_rectangle_frame(vec3 corner, vec3 ex, vec3 ey, RectangleFrame& out);
/// Returns false (and solid_angle 0) when the rectangle is degenerate as seen from ref. Float throughout: the solid
/// angle is a sum of corner angles split into exact quarter turns plus small remainders, which keeps about 1e-3
/// relative precision down to 3e-4 sr (below that the lights fall back to area sampling). Trigonometry comes from
/// core/fast_trig.h: two polynomial atan2 per setup; one sincosf per sample.
bool make_spherical_rectangle(vec3 ref, const RectangleFrame& rect, SphericalRectangle& out);
/// The same from the corner and edges (makes the frame first).
bool make_spherical_rectangle(vec3 ref, vec3 corner, vec3 ex, vec3 ey, SphericalRectangle& out);
/// A point on the rectangle; its density in solid angle at ref is 1 / solid_angle.
vec3 sample_spherical_rectangle(const SphericalRectangle& sr, vec2 u);

/// The solid angle subtended by the triangle (p0, p0 + e1, p0 + e2) at `ref`, with what is needed to sample it
/// uniformly in solid angle (Arvo 1995, "Stratified Sampling of Spherical Triangles"; pbrt-v4's
/// SampleSphericalTriangle). Uniform area sampling has a density in solid angle proportional to d^2 / cos, which is
/// far from constant for a large or nearby triangle; this one is exactly constant, 1 / solid_angle.
struct SphericalTriangle {
  vec3 o{0.0f}, p0{0.0f}, e1{0.0f}, e2{0.0f};  ///< ref and the triangle, to turn a direction into a point
  vec3 a{0.0f}, b{0.0f}, c{0.0f};  ///< unit directions from ref to p0 (Arvo's A), p0 + e1 (B) and p0 + e2 (C)
  vec3 c_perp{0.0f};               ///< unit tangent at a of the great-circle arc from a toward c
  float sin_alpha = 0, cos_alpha = 0;  ///< of the interior angle at a
  float tan_half_ab = 0, tan_half_ac = 0;  ///< tan of half the arcs a-b and a-c
  float solid_angle = 0;           ///< steradians; 0 if degenerate (ref in the plane, ...)
};
/// Returns false (and solid_angle 0) when the triangle is degenerate as seen from ref. Float throughout: the solid
/// angle is Van Oosterom and Strackee's 2 atan2(|a.(b x c)|, 1 + a.b + b.c + c.a) with the triple product taken
/// from the edges and the dot products from chord lengths, so small and grazing triangles keep their relative
/// precision (the lights use it only above 3e-4 sr, as for rectangles).
bool make_spherical_triangle(vec3 ref, vec3 p0, vec3 e1, vec3 e2, SphericalTriangle& out);
/// A point on the triangle; its density in solid angle at ref is 1 / solid_angle. u.x picks the sub-triangle of
/// area u.x * solid_angle, u.y the point along its last arc (Arvo's two steps, so strata of u stay strata).
vec3 sample_spherical_triangle(const SphericalTriangle& st, vec2 u);

/// A parallelogram (p0, p0 + e1, p0 + e1 + e2, p0 + e2) as two spherical triangles split at the diagonal from p0:
/// its solid angle is their sum, and picking one in proportion to its solid angle, then a direction uniformly in it,
/// samples the whole parallelogram uniformly in solid angle. Spherical rectangles (Urena et al. 2013) need right
/// angles and pbrt-v4 samples other bilinear patches by area; this gives sheared quads (glTF and OBJ lights that are
/// not rectangles) the same constant density, at the price of two triangle setups (issue 11).
struct SphericalParallelogram {
  SphericalTriangle t[2];  ///< (p0 + e1, p0, p0 + e1 + e2) and (p0 + e1 + e2, p0, p0 + e2): halves at the diagonal
  float solid_angle = 0;   ///< of both; 0 if degenerate
};
/// False (solid_angle 0) when either half is degenerate as seen from ref (ref in the plane, ...).
bool make_spherical_parallelogram(vec3 ref, vec3 p0, vec3 e1, vec3 e2, SphericalParallelogram& out);
/// A point on the parallelogram; its density in solid angle at ref is 1 / solid_angle. u.x runs over the first
/// triangle's solid angle, then the second's, and the map is continuous across the diagonal, so a stratum of u stays
/// one region of the light; u.y as in sample_spherical_triangle.
vec3 sample_spherical_parallelogram(const SphericalParallelogram& sp, vec2 u);

/// A discrete distribution over indices, proportional to non-negative weights (used to pick a light by power).
struct DiscreteDistribution {
  std::vector<float> cdf;  ///< size n + 1, cdf[0] = 0, cdf[n] = 1
  std::vector<float> pmf_table;

  DiscreteDistribution() = default;
  /// Weights must be finite and >= 0; if all are 0 every index gets equal probability.
  explicit DiscreteDistribution(std::span<const float> weights);
  size_t size() const { return pmf_table.size(); }
  float pmf(size_t i) const { return pmf_table[i]; }
  /// Index for u in [0,1). Optionally returns its pmf and u remapped to [0,1) within the chosen bucket (for reuse).
  /// A single bucket (a scene with one light, the common case) is answered inline, without the search.
  size_t sample(float u, float* pmf_out = nullptr, float* u_remapped = nullptr) const {
    if (pmf_table.size() != 1) return search(u, pmf_out, u_remapped);
    if (pmf_out) *pmf_out = pmf_table[0];
    if (u_remapped) *u_remapped = std::clamp(u, 0.0f, kOneMinusEpsilon);
    return 0;
  }

 private:
  size_t search(float u, float* pmf_out, float* u_remapped) const;
};

}  // namespace pt
