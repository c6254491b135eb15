#include "core/sampling.h"

#include <algorithm>
#include <bit>
#include <numeric>

#include "core/chord_sine.h"
#include "core/fast_trig.h"
#include "core/frame.h"

namespace pt {

vec2 sample_uniform_disk_concentric(vec2 u) {
  float radius;
  return concentric_map(u, radius);
}

vec3 sample_uniform_sphere(vec2 u) {
  float z = 1.0f - 2.0f * u.x;
  float r = safe_sqrt(1.0f - z * z);
  float phi = kTwoPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
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

namespace {

/// 2^-e for the power of two 2^e <= m (m positive, normal, below 2^127): an exact scale factor without a division.
float inverse_power_of_two(float m) {
  return std::bit_cast<float>(0x7f000000u - (std::bit_cast<uint32_t>(m) & 0x7f800000u));
}

}  // namespace

bool make_rectangle_frame(vec3 corner, vec3 ex, vec3 ey, RectangleFrame& rect) {
  rect = RectangleFrame{};
  const float ex_len = glm::length(ex), ey_len = glm::length(ey);
  if (!(ex_len > 0.0f) || !(ey_len > 0.0f) || !std::isfinite(ex_len * ey_len)) return false;
  rect.corner = corner;
  rect.x = ex / ex_len;
  rect.y = ey / ey_len;
  rect.z = glm::cross(rect.x, rect.y);
  rect.len_x = ex_len;
  rect.len_y = ey_len;
  return true;
}

bool make_spherical_rectangle(vec3 ref, const RectangleFrame& rect, SphericalRectangle& sr) {
  sr = SphericalRectangle{};
  if (!(rect.len_x > 0.0f)) return false;
  vec3 z = rect.z;
  const vec3 d = rect.corner - ref;
  float z0 = glm::dot(d, z);
  if (z0 > 0.0f) {  // make z point away from the rectangle plane
    z = -z;
    z0 = -z0;
  }
  if (!(z0 < 0.0f)) return false;  // ref in the plane
  const float x0 = glm::dot(d, rect.x), y0 = glm::dot(d, rect.y), x1 = x0 + rect.len_x, y1 = y0 + rect.len_y;
  // The solid angle is F(x1,y1) - F(x1,y0) - F(x0,y1) + F(x0,y0) with F(x,y) = atan(x y / (h R(x,y))), h = -z0,
  // R the distance to the corner (the closed form behind Urena et al.'s angles gamma_i = pi/2 + a_i, written with
  // atan2 of well-conditioned products instead of acos of dot products of normals, so float suffices). The four
  // corner angles are added two by two as arguments of complex products (q0 + i p0)(q1 + i p1): each term has
  // q > 0, so a pair's sum lies in (-pi, pi) and one atan2 gives it. The lengths are scaled to at most 1 first,
  // so the products of four lengths neither overflow nor underflow (the angles do not depend on the scale).
  const float h = -z0;
  const float longest =
      std::max(std::max(std::max(std::abs(x0), std::abs(x1)), std::max(std::abs(y0), std::abs(y1))), h);
  if (!(longest < 0x1p126f)) return false;  // NaN or beyond the scale factor's range
  const float scale = inverse_power_of_two(longest);
  const float sh = h * scale, sh2 = sh * sh;
  const float cx[4] = {x1 * scale, x1 * scale, -x0 * scale, x0 * scale};
  const float cy[4] = {-y0 * scale, y1 * scale, y1 * scale, y0 * scale};
  float p[4], q[4];
  for (int i = 0; i < 4; ++i) {
    p[i] = cx[i] * cy[i];
    q[i] = sh * std::sqrt(cx[i] * cx[i] + cy[i] * cy[i] + sh2);
  }
  const SplitAngle a01 = split_atan2(q[0] * p[1] + p[0] * q[1], q[0] * q[1] - p[0] * p[1]);
  const SplitAngle a23 = split_atan2(q[2] * p[3] + p[2] * q[3], q[2] * q[3] - p[2] * p[3]);
  const float solid_angle = float(a01.quarter + a23.quarter) * (0.5f * kPi) + (a01.rest + a23.rest);
  if (!(solid_angle > 0.0f) || !std::isfinite(solid_angle)) return false;
  sr.o = ref;
  sr.x = rect.x;
  sr.y = rect.y;
  sr.z = z;
  sr.z0 = z0;
  sr.x0 = x0;
  sr.y0 = y0;
  sr.x1 = x1;
  sr.y1 = y1;
  ChordSine c0, c1;
  chord_sines(-y0, y1, h * h, c0, c1);
  sr.b0 = c0.sine;
  sr.b0p = h * c0.inv_r;
  sr.b1 = c1.sine;
  sr.k = a23.rest;
  sr.odd_quarters = (a23.quarter & 1) != 0;
  sr.quarter_sign = a23.quarter == 0 || a23.quarter == 1 ? 1.0f : -1.0f;
  sr.even_sum = a23.quarter == 0 ? c1.one_plus - c0.one_minus : c0.one_minus - c1.one_minus;
  sr.solid_angle = solid_angle;
  return true;
}

bool make_spherical_rectangle(vec3 ref, vec3 corner, vec3 ex, vec3 ey, SphericalRectangle& out) {
  RectangleFrame rect;
  if (!make_rectangle_frame(corner, ex, ey, rect)) {
    out = SphericalRectangle{};
    return false;
  }
  return make_spherical_rectangle(ref, rect, out);
}

vec3 sample_spherical_rectangle(const SphericalRectangle& sr, vec2 u) {
  // Urena et al. 2013, section 4: invert the solid angle along x, then sample y uniformly in the projected chord.
  // Their angle au = u S + k is written as pi + t - q pi/2 with t = u S - rest small-ish and q an integer, so cos
  // and sin of au come exactly from those of t, and their numerator cos(au) b0 - b1 (a difference of numbers near
  // 1 for far or grazing views) from the exact 1 -+ b terms. Their x = -cu z0 / sqrt(1 - cu^2), with
  // cu = sign(fu) / sqrt(fu^2 + b0^2), is rewritten as h sign(fu) / sqrt((|fu| - b0')(|fu| + b0')),
  // b0' = sqrt(1 - b0^2), which does not lose x to the rounding of cu near 1.
  const float h = -sr.z0;
  const float t = u.x * sr.solid_angle - sr.k;
  const float sin_half = std::sin(0.5f * t), cos_half = std::cos(0.5f * t);  // one sincosf call
  const float sin_t = 2.0f * sin_half * cos_half, cos_t = 1.0f - 2.0f * sin_half * sin_half;
  // num = cos(delta) b0 + b1 and den = sin(delta), delta = au - pi = t - q pi / 2. q even: cos(delta) = sign cos t,
  // sin(delta) = sign sin t, and num = even_sum - sign b0 (1 - cos t) with 1 - cos t = 2 sin^2(t / 2). q odd:
  // cos(delta) = sign sin t, sin(delta) = -sign cos t. Both are computed and one is selected: q varies from one
  // receiver to the next, and a mispredicted branch costs more than the few multiplications.
  const float sign = sr.quarter_sign;
  const float num_even = sr.even_sum - sign * sr.b0 * (2.0f * sin_half * sin_half), den_even = sign * sin_t;
  const float num_odd = sign * sin_t * sr.b0 + sr.b1, den_odd = -sign * cos_t;
  const float num = sr.odd_quarters ? num_odd : num_even, den = sr.odd_quarters ? den_odd : den_even;
  // fu = num / den; x = h sign(fu) / sqrt((|fu| - b0')(|fu| + b0')), multiplied through by |den|.
  const float an = std::abs(num), ad = std::abs(den);
  const float qq = std::max((an - sr.b0p * ad) * (an + sr.b0p * ad), 0.0f);
  const uint32_t sign_bit = (std::bit_cast<uint32_t>(num) ^ std::bit_cast<uint32_t>(den)) & 0x80000000u;
  float xu = std::bit_cast<float>(std::bit_cast<uint32_t>(h) ^ sign_bit) * ad / std::sqrt(qq);  // +-inf where qq = 0
  xu = std::isnan(xu) ? 0.5f * (sr.x0 + sr.x1) : xu;  // only where delta and fu vanish together
  xu = std::clamp(xu, sr.x0, sr.x1);
  const float d2 = xu * xu + h * h;
  ChordSine e0, e1;
  chord_sines(sr.y0, sr.y1, d2, e0, e1);
  const float m0 = e0.one_minus, p0 = e0.one_plus, m1 = e1.one_minus, p1 = e1.one_plus;
  // hv = h0 + u (h1 - h0) with h = sin of the elevation; 1 - hv and 1 + hv interpolated from their exact ends.
  float one_minus = m0 + u.y * (m1 - m0), one_plus = p0 + u.y * (p1 - p0);
  float hv = 0.5f * (one_plus - one_minus);
  float denom = one_minus * one_plus;
  float yv = denom > 0.0f ? hv * std::sqrt(d2 / denom) : (hv > 0.0f ? sr.y1 : sr.y0);
  yv = std::clamp(yv, sr.y0, sr.y1);
  return sr.o + xu * sr.x + yv * sr.y + sr.z0 * sr.z;
}

bool make_spherical_triangle(vec3 ref, vec3 p0, vec3 e1, vec3 e2, SphericalTriangle& st) {
  st = SphericalTriangle{};
  const vec3 pa = p0 - ref, pb = pa + e1, pc = pa + e2;
  const float la = glm::length(pa), lb = glm::length(pb), lc = glm::length(pc);
  if (!(la > 0.0f) || !(lb > 0.0f) || !(lc > 0.0f) || !std::isfinite(la + lb + lc)) return false;
  const vec3 a = pa / la, b = pb / lb, c = pc / lc;
  // The triple product a.(b x c) = det(pa, e1, e2) / (la lb lc): from the exact edges, it does not cancel when the
  // three directions are nearly parallel (a small or far triangle). Dot products of unit vectors are written as
  // x.y = 1 - |x - y|^2 / 2: the chords are small where the dot products would round to 1.
  const float det = std::abs(glm::dot(a, glm::cross(e1 / lb, e2 / lc)));
  const vec3 ab = b - a, ac = c - a, bc = c - b;
  const float ab2 = glm::dot(ab, ab), ac2 = glm::dot(ac, ac), bc2 = glm::dot(bc, bc);
  const SplitAngle half_angle = split_atan2(det, 4.0f - 0.5f * (ab2 + ac2 + bc2));  // Van Oosterom-Strackee
  const float solid_angle = float(half_angle.quarter) * kPi + 2.0f * half_angle.rest;
  if (!(det > 0.0f) || !(solid_angle > 0.0f) || !std::isfinite(solid_angle)) return false;
  // The interior angle at a is the angle between the planes (a, b) and (a, c): its sine and cosine, times
  // |a x b| |a x c|, are |a.(b x c)| and (a x b).(a x c) = b.c - (a.b)(a.c) = ab.ac - |ab|^2 |ac|^2 / 4.
  const float cos_scaled = glm::dot(ab, ac) - 0.25f * ab2 * ac2;
  const float scale = std::sqrt(det * det + cos_scaled * cos_scaled);
  const vec3 tangent = ac + (0.5f * ac2) * a;  // c - (a.c) a: the direction of the arc a -> c at a
  const float tangent_len = glm::length(tangent), sum_ab = glm::length(a + b), sum_ac = glm::length(a + c);
  if (!(scale > 0.0f) || !(tangent_len > 0.0f) || !(sum_ab > 0.0f) || !(sum_ac > 0.0f)) return false;
  st.o = ref;
  st.p0 = p0;
  st.e1 = e1;
  st.e2 = e2;
  st.a = a;
  st.b = b;
  st.c = c;
  st.c_perp = tangent / tangent_len;
  st.sin_alpha = det / scale;
  st.cos_alpha = cos_scaled / scale;
  st.tan_half_ab = std::sqrt(ab2) / sum_ab;  // tan(theta / 2) = |x - y| / |x + y| for unit x, y
  st.tan_half_ac = std::sqrt(ac2) / sum_ac;
  st.solid_angle = solid_angle;
  return std::isfinite(st.tan_half_ab) && std::isfinite(st.tan_half_ac);
}

vec3 sample_spherical_triangle(const SphericalTriangle& st, vec2 u) {
  // Arvo 1995: the point c' on the arc a -> c such that the triangle (a, b, c') has area A' = u.x * solid_angle,
  // then a point on the arc b -> c' uniform in 1 - cos of its distance to b. Arvo writes cos|ac'| as a ratio of
  // differences of products of sines and cosines, which cancel for small triangles; we solve the half-angle
  // excess formula tan(E / 2) = t tan(|ac'| / 2) sin(alpha) / (1 + t tan(|ac'| / 2) cos(alpha)), t = tan(|ab| / 2),
  // for the arc instead: tan(|ac'| / 2) = y / x with y = sin(A' / 2), x = t sin(alpha - A' / 2) (positive for every
  // A' up to the full area), and take cos and sin of the arc from that tangent without any inverse trigonometry.
  const float half = 0.5f * u.x * st.solid_angle;
  const float y = std::sin(half), ch = std::cos(half);
  const float x = st.tan_half_ab * (st.sin_alpha * ch - st.cos_alpha * y);
  vec3 cp = st.c;  // the whole arc: u.x = 1, or rounding past it
  if (x > 0.0f && y < x * st.tan_half_ac) {
    const float r2 = x * x + y * y;
    cp = ((x - y) * (x + y) / r2) * st.a + (2.0f * x * y / r2) * st.c_perp;
  }
  const vec3 d = cp - st.b;
  const float k = 0.5f * glm::dot(d, d);  // 1 - b.c', from the chord
  const float one_minus_cos = u.y * k;
  const float cos_t = 1.0f - one_minus_cos, sin_t = safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
  const vec3 tangent = d + k * st.b;  // c' - (b.c') b
  const float tangent_len = glm::length(tangent);
  const vec3 w = tangent_len > 0.0f ? cos_t * st.b + (sin_t / tangent_len) * tangent : st.b;
  // The point where ref + t w meets the triangle, as barycentrics (Moller-Trumbore), clamped onto the triangle.
  const vec3 s = st.o - st.p0, s1 = glm::cross(w, st.e2);
  const float inv = 1.0f / glm::dot(s1, st.e1);
  float b1 = glm::dot(s, s1) * inv, b2 = glm::dot(w, glm::cross(s, st.e1)) * inv;
  if (!std::isfinite(b1) || !std::isfinite(b2)) b1 = b2 = 1.0f / 3.0f;  // w in the plane: only when degenerate
  b1 = std::clamp(b1, 0.0f, 1.0f);
  b2 = std::clamp(b2, 0.0f, 1.0f);
  if (b1 + b2 > 1.0f) {
    const float sum = b1 + b2;
    b1 /= sum;
    b2 /= sum;
  }
  return st.p0 + b1 * st.e1 + b2 * st.e2;
}

bool make_spherical_parallelogram(vec3 ref, vec3 p0, vec3 e1, vec3 e2, SphericalParallelogram& out) {
  // Arvo's sampling ends (u.x -> 1) on its triangle's arc b -> c and starts (u.x -> 0) on the arc b -> a. With the
  // diagonal as the first triangle's b -> c and the second's b -> a, both from p0, the two halves meet there.
  const vec3 p1 = p0 + e1, p2 = p1 + e2;
  out.solid_angle = 0.0f;
  if (!make_spherical_triangle(ref, p1, -e1, e2, out.t[0]) ||
      !make_spherical_triangle(ref, p2, -(e1 + e2), -e1, out.t[1]))
    return false;
  out.solid_angle = out.t[0].solid_angle + out.t[1].solid_angle;
  return out.solid_angle > 0.0f;
}

vec3 sample_spherical_parallelogram(const SphericalParallelogram& sp, vec2 u) {
  const float a = u.x * sp.solid_angle, first = sp.t[0].solid_angle, second = sp.t[1].solid_angle;
  if (a < first || !(second > 0.0f))
    return sample_spherical_triangle(sp.t[0], {std::min(a / first, kOneMinusEpsilon), u.y});
  return sample_spherical_triangle(sp.t[1], {std::clamp((a - first) / second, 0.0f, kOneMinusEpsilon), u.y});
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

size_t DiscreteDistribution::search(float u, float* pmf_out, float* u_remapped) const {
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
