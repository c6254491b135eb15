// Light sampling against its claimed densities (chi-square), through sample_light, the code the integrator runs:
// rectangle lights by area and by solid angle, a two-triangle OBJ-style light merged into one parallelogram light,
// sheared parallelograms by solid angle (two spherical triangles), triangle lights by solid angle, sphere lights by
// cone.
#include <gtest/gtest.h>

#include "../core/chi_square.h"
#include "core/frame.h"
#include "core/rng.h"
#include "render/light.h"
#include "render/render_scene.h"
#include "scene_builders.h"

namespace pt {
namespace {

// 10 chi-square tests in this file (counting each reference point); Bonferroni keeps the family's false alarm
// rate below 1%.
const double kAlpha = 0.01 / 10;

/// Chi-square of sample_light's points on a rectangle light over the rectangle's (a, b) parameters against the
/// density it claims: pdf(omega) * d omega / d(a, b) = ls.pdf * area * cos_l / dist^2 must be what sample_light
/// returns as ls.pdf, and the points must follow it.
test::ChiSquareResult rect_chi_square(const Light& l, vec3 ref, LightSampling mode, uint64_t seed) {
  const float l1 = glm::length(l.e1), l2 = glm::length(l.e2);
  auto sample = [&](vec2 u) {
    LightSample ls;
    if (!sample_light(l, ref, u, mode, ls)) return vec2(-1.0f);
    vec3 p = ls.point.p - l.p0;
    return vec2(glm::dot(p, l.e1) / (l1 * l1), glm::dot(p, l.e2) / (l2 * l2));
  };
  auto density = [&](vec2 x) {
    vec3 p = l.p0 + x.x * l.e1 + x.y * l.e2;
    vec3 d = p - ref;
    double dist = glm::length(d);
    double cos_l = std::abs(glm::dot(d, l.n)) / dist;
    float pdf = light_pdf(l, ref, vec3(d / float(dist)), float(dist), l.n, mode);
    return double(pdf) * l.area * cos_l / (dist * dist);
  };
  return test::chi_square_2d(sample, density, 20, 20, 400000, seed);
}

TEST(LightSampling, RectangleByAreaIsUniformOverTheRectangle) {
  Light l = make_rect_light(vec3(-0.5f, 1, -0.3f), vec3(1.2f, 0, 0), vec3(0, 0.2f, 0.8f), vec3(1));
  vec3 ref(0.1f, -0.5f, 0.2f);
  ASSERT_GT(glm::dot(ref - l.p0, l.n), 0.0f);  // in front of the light
  float l1 = glm::length(l.e1), l2 = glm::length(l.e2);
  auto r = test::chi_square_2d(
      [&](vec2 u) {
        LightSample ls;
        if (!sample_light(l, ref, u, LightSampling::area, ls)) return vec2(-1.0f);
        vec3 p = ls.point.p - l.p0;
        return vec2(glm::dot(p, l.e1) / (l1 * l1), glm::dot(p, l.e2) / (l2 * l2));
      },
      [](vec2) { return 1.0; }, 20, 20, 400000, 21);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
}

TEST(LightSampling, RectangleBySolidAngleFollowsItsPdf) {
  Light l = make_rect_light(vec3(-0.5f, 1, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1), vec3(1));  // faces -y
  vec3 ref(0.3f, 0.4f, 0.2f);
  SphericalRectangle sr;
  ASSERT_TRUE(make_spherical_rectangle(ref, l.p0, l.e1, l.e2, sr));
  ASSERT_GT(sr.solid_angle, 3e-4f);  // inside the solid-angle range, so this is the spherical-rectangle path
  ASSERT_LT(sr.solid_angle, 6.22f);
  auto r = rect_chi_square(l, ref, LightSampling::solid_angle, 23);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
  EXPECT_NEAR(r.expected_total / 400000, 1.0, 2e-3);
}

/// An emissive quad (corners in order, in the plane y = 1) as an OBJ delivers it, two triangles sharing the diagonal
/// 0-2, wound clockwise seen from above so the light faces down, over a floor triangle. Other splits and windings
/// of the quad by `first` and `second`.
RenderScene obj_quad_light_scene(const vec3 (&quad)[4], uvec3 first = uvec3(0, 1, 2), uvec3 second = uvec3(0, 2, 3)) {
  Scene s;
  uint32_t white = test::add_material(s, test::diffuse(vec3(0.5f)));
  uint32_t light = test::add_material(s, test::diffuse(vec3(0.0f), vec3(4.0f)));
  Mesh m;
  m.positions = {quad[0], quad[1], quad[2], quad[3], vec3(-5, 0, -5), vec3(5, 0, -5), vec3(5, 0, 5)};
  m.indices = {first, second, uvec3(4, 6, 5)};
  m.materials = {light, light, white};
  s.meshes.push_back(m);
  return make_render_scene(s);
}

TEST(LightSampling, TwoTrianglesOfAQuadBecomeOneSolidAngleSampledLight) {
  // An OBJ quad arrives as two triangles sharing a diagonal; they must become one rectangle light that both
  // triangles map to, sampled by solid angle.
  RenderScene rs =
      obj_quad_light_scene({vec3(-0.5f, 1, -0.5f), vec3(0.5f, 1, -0.5f), vec3(0.5f, 1, 0.5f), vec3(-0.5f, 1, 0.5f)});
  ASSERT_EQ(rs.lights.lights.size(), 1u);
  EXPECT_EQ(rs.tri_light[0], 0);
  EXPECT_EQ(rs.tri_light[1], 0);
  EXPECT_EQ(rs.tri_light[2], -1);
  const Light& l = rs.lights.lights[0];
  ASSERT_EQ(l.kind, LightKind::rect);
  EXPECT_TRUE(l.rectangular);
  EXPECT_NEAR(l.area, 1.0f, 1e-6f);
  EXPECT_NEAR(l.n.y, -1.0f, 1e-6f);
  vec3 ref = vec3(0.3f, 0.4f, 0.2f) - rs.geo->origin;
  auto r = rect_chi_square(l, ref, LightSampling::solid_angle, 24);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
  EXPECT_NEAR(r.expected_total / 400000, 1.0, 2e-3);
}

/// The (a, b) with p = p0 + a e1 + b e2 for a point p in the light's plane, by the inverse Gram matrix of its edges
/// (which need not be orthogonal), in double.
glm::dvec2 affine_coordinates(const Light& l, vec3 p) {
  const dvec3 e1(l.e1), e2(l.e2), q = dvec3(p) - dvec3(l.p0);
  const double g11 = glm::dot(e1, e1), g12 = glm::dot(e1, e2), g22 = glm::dot(e2, e2), det = g11 * g22 - g12 * g12;
  const double r1 = glm::dot(q, e1), r2 = glm::dot(q, e2);
  return {(g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det};
}

/// The same for any parallelogram light, over its affine coordinates (a, b) in [0,1]^2 (p = p0 + a e1 + b e2, found
/// with the inverse Gram matrix, so the edges need not be orthogonal): the claimed density there is
/// ls.pdf * area * cos_l / dist^2.
test::ChiSquareResult parallelogram_chi_square(const Light& l, vec3 ref, LightSampling mode, uint64_t seed) {
  auto sample = [&](vec2 u) {
    LightSample ls;
    return sample_light(l, ref, u, mode, ls) ? vec2(affine_coordinates(l, ls.point.p)) : vec2(-1.0f);
  };
  auto density = [&](vec2 x) {
    vec3 d = l.p0 + x.x * l.e1 + x.y * l.e2 - ref;
    double dist = glm::length(d);
    double cos_l = std::abs(glm::dot(d, l.n)) / dist;
    float pdf = light_pdf(l, ref, vec3(d / float(dist)), float(dist), l.n, mode);
    return double(pdf) * l.area * cos_l / (dist * dist);
  };
  return test::chi_square_2d(sample, density, 20, 20, 400000, seed);
}

/// The solid angle of a parallelogram at ref by Van Oosterom and Strackee's formula for each half, in double: an
/// independent check of SphericalParallelogram's.
double parallelogram_solid_angle(const Light& l, vec3 ref) {
  auto tri = [&](dvec3 a, dvec3 b, dvec3 c) {
    const dvec3 o(ref);
    a -= o, b -= o, c -= o;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = std::abs(glm::dot(a, glm::cross(b, c)));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    return 2.0 * std::atan2(num, den);
  };
  const dvec3 p0(l.p0), p1 = p0 + dvec3(l.e1), p2 = p1 + dvec3(l.e2), p3 = p0 + dvec3(l.e2);
  return tri(p0, p1, p2) + tri(p0, p2, p3);
}

TEST(LightSampling, ParallelogramBySolidAngleFollowsItsPdf) {
  // A sheared quad (60 degrees between its edges), so no spherical rectangle applies: below it (0.5 sr), close to
  // it (5 sr: area sampling's density is far from uniform) and far away (2.6e-3 sr).
  Light l = make_rect_light(vec3(-0.6f, 1, -0.4f), vec3(1.0f, 0, 0), vec3(0.4f, 0, 0.7f), vec3(1));
  ASSERT_FALSE(l.rectangular);
  ASSERT_LT(l.n.y, -0.99f);  // faces -y
  const vec3 refs[] = {vec3(0.1f, 0.0f, 0.1f), vec3(0.05f, 0.93f, -0.05f), vec3(3.0f, -6.0f, 4.0f)};
  for (int i = 0; i < 3; ++i) {
    const double omega = parallelogram_solid_angle(l, refs[i]);
    ASSERT_GT(omega, 3e-4);  // inside the solid-angle range, so this is the spherical path
    ASSERT_LT(omega, 6.22);
    LightSample ls;
    ASSERT_TRUE(sample_light(l, refs[i], vec2(0.3f, 0.6f), LightSampling::solid_angle, ls));
    EXPECT_NEAR(ls.pdf, 1.0 / omega, 2e-4 / omega) << "ref " << i;
    auto r = parallelogram_chi_square(l, refs[i], LightSampling::solid_angle, 31 + i);
    EXPECT_GT(r.p_value, kAlpha) << "ref " << i << " " << r.describe();
    EXPECT_NEAR(r.expected_total / 400000, 1.0, 2e-3) << "ref " << i;
  }
}

TEST(LightSampling, SphericalParallelogramKeepsStrataAndStaysOnTheLight) {
  // u.x runs over the first triangle's solid angle, then the second's: the map is monotone in u.x and continuous
  // across the diagonal (the two halves meet there), so a stratum of u stays one region of the light.
  SphericalParallelogram sp;
  const vec3 p0(-0.6f, 1, -0.4f), e1(1.0f, 0, 0), e2(0.4f, 0, 0.7f), ref(0.1f, 0.0f, 0.1f);
  ASSERT_TRUE(make_spherical_parallelogram(ref, p0, e1, e2, sp));
  const float split = sp.t[0].solid_angle / sp.solid_angle;
  for (float v : {0.1f, 0.5f, 0.9f}) {
    const vec3 below = sample_spherical_parallelogram(sp, {std::nextafter(split, 0.0f), v});
    const vec3 above = sample_spherical_parallelogram(sp, {std::nextafter(split, 1.0f), v});
    EXPECT_LT(glm::length(below - above), 1e-4f) << v;
  }
  // Every sample lies on the parallelogram: its affine coordinates (a, b) in the plane y = 1 are in [0, 1].
  Pcg32 rng(5, 6);
  for (int k = 0; k < 10000; ++k) {
    const vec3 q = sample_spherical_parallelogram(sp, {rng.next_float(), rng.next_float()}) - p0;
    const float det = e1.x * e2.z - e1.z * e2.x;
    const float a = (q.x * e2.z - q.z * e2.x) / det, b = (e1.x * q.z - e1.z * q.x) / det;
    ASSERT_GE(a, -1e-5f) << k;
    ASSERT_LE(a, 1.0f + 1e-5f) << k;
    ASSERT_GE(b, -1e-5f) << k;
    ASSERT_LE(b, 1.0f + 1e-5f) << k;
    ASSERT_NEAR(q.y, 0.0f, 1e-6f) << k;
  }
}

TEST(LightSampling, TwoTrianglesOfAShearedQuadBecomeOneSolidAngleSampledParallelogram) {
  // An OBJ quad that is not a rectangle still merges into one light; it is sampled by its two spherical triangles.
  RenderScene rs =
      obj_quad_light_scene({vec3(-0.6f, 1, -0.4f), vec3(0.4f, 1, -0.4f), vec3(0.8f, 1, 0.3f), vec3(-0.2f, 1, 0.3f)});
  ASSERT_EQ(rs.lights.lights.size(), 1u);
  const Light& l = rs.lights.lights[0];
  ASSERT_EQ(l.kind, LightKind::rect);
  EXPECT_FALSE(l.rectangular);
  EXPECT_NEAR(l.area, 0.7f, 1e-5f);
  vec3 ref = vec3(0.1f, 0.4f, 0.0f) - rs.geo->origin;
  auto r = parallelogram_chi_square(l, ref, LightSampling::solid_angle, 34);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
  EXPECT_NEAR(r.expected_total / 400000, 1.0, 2e-3);
}

TEST(LightSampling, EmissiveTrianglePairsMergeOnlyIntoTheirOwnParallelogram) {
  // Exporters split a quad along either diagonal and start each triangle at any corner: every such pair is one
  // light, facing the way its triangles do. A pair that is not exactly a parallelogram, or whose triangles face
  // opposite ways, stays two triangle lights: a merged light would emit from a surface (or a side) that is not
  // the triangles', and light_pdf would not match hits on them.
  const vec3 quad[4] = {vec3(-0.6f, 1, -0.4f), vec3(0.4f, 1, -0.4f), vec3(0.8f, 1, 0.3f), vec3(-0.2f, 1, 0.3f)};
  const uvec3 splits[][2] = {{uvec3(0, 1, 2), uvec3(0, 2, 3)}, {uvec3(0, 1, 2), uvec3(2, 3, 0)},
                             {uvec3(2, 3, 0), uvec3(1, 2, 0)}, {uvec3(0, 1, 3), uvec3(1, 2, 3)},
                             {uvec3(1, 2, 3), uvec3(3, 0, 1)}, {uvec3(3, 0, 1), uvec3(2, 3, 1)}};
  for (const auto& split : splits) {
    RenderScene rs = obj_quad_light_scene(quad, split[0], split[1]);
    SCOPED_TRACE(testing::Message() << "split " << split[0].x << split[0].y << split[0].z << " / " << split[1].x
                                    << split[1].y << split[1].z);
    ASSERT_EQ(rs.lights.lights.size(), 1u);
    EXPECT_EQ(rs.tri_light[0], 0);
    EXPECT_EQ(rs.tri_light[1], 0);
    const Light& l = rs.lights.lights[0];
    EXPECT_EQ(l.kind, LightKind::rect);
    EXPECT_NEAR(l.area, 0.7f, 1e-5f);
    EXPECT_NEAR(l.n.y, -1.0f, 1e-6f);  // the triangles' front, down
  }
  // The fourth corner 1% of the quad's size off the parallelogram: two triangles.
  vec3 kite[4] = {quad[0], quad[1], quad[2], quad[3] + vec3(0.0f, 0.0f, 0.01f)};
  RenderScene off = obj_quad_light_scene(kite);
  ASSERT_EQ(off.lights.lights.size(), 2u);
  for (const Light& l : off.lights.lights) EXPECT_EQ(l.kind, LightKind::triangle);
  // The second triangle wound the other way: two triangle lights facing opposite ways.
  RenderScene flipped = obj_quad_light_scene(quad, uvec3(0, 1, 2), uvec3(0, 3, 2));
  ASSERT_EQ(flipped.lights.lights.size(), 2u);
  EXPECT_EQ(flipped.lights.lights[0].kind, LightKind::triangle);
  EXPECT_EQ(flipped.lights.lights[1].kind, LightKind::triangle);
  EXPECT_NEAR(flipped.lights.lights[0].n.y, -1.0f, 1e-6f);
  EXPECT_NEAR(flipped.lights.lights[1].n.y, 1.0f, 1e-6f);
}

/// The same for a triangle light, over the (x, y) in [0,1]^2 of the inverse square-root warp (b1 + b2 = sqrt(x),
/// b1 = sqrt(x) y), which is uniform by area: the claimed density there is ls.pdf * area * cos_l / dist^2.
test::ChiSquareResult tri_chi_square(const Light& l, vec3 ref, LightSampling mode, uint64_t seed) {
  auto sample = [&](vec2 u) {
    LightSample ls;
    if (!sample_light(l, ref, u, mode, ls)) return vec2(-1.0f);
    const glm::dvec2 b = affine_coordinates(l, ls.point.p);  // barycentrics b1, b2
    const double s = b.x + b.y;
    return vec2(float(s * s), s > 0.0 ? float(b.x / s) : 0.0f);
  };
  auto density = [&](vec2 x) {
    const float s = std::sqrt(x.x);
    vec3 d = l.p0 + s * x.y * l.e1 + s * (1.0f - x.y) * l.e2 - ref;
    double dist = glm::length(d);
    double cos_l = std::abs(glm::dot(d, l.n)) / dist;
    float pdf = light_pdf(l, ref, vec3(d / float(dist)), float(dist), l.n, mode);
    return double(pdf) * l.area * cos_l / (dist * dist);
  };
  return test::chi_square_2d(sample, density, 20, 20, 400000, seed);
}

TEST(LightSampling, TriangleBySolidAngleFollowsItsPdf) {
  // Below a triangle (0.48 sr), close to it (5.5 sr: a density in area far from uniform) and far away (6.5e-3 sr).
  Light l = make_triangle_light(vec3(-0.5f, 1, -0.5f), vec3(0.5f, 1, -0.5f), vec3(0, 1, 0.7f), vec3(1));  // faces -y
  const vec3 refs[] = {vec3(0.1f, 0.0f, 0.1f), vec3(0.05f, 0.95f, -0.1f), vec3(3.0f, -6.0f, 4.0f)};
  for (int i = 0; i < 3; ++i) {
    SphericalTriangle st;
    ASSERT_TRUE(make_spherical_triangle(refs[i], l.p0, l.e1, l.e2, st));
    ASSERT_GT(st.solid_angle, 3e-4f);  // inside the solid-angle range, so this is the spherical-triangle path
    ASSERT_LT(st.solid_angle, 6.22f);
    LightSample ls;
    ASSERT_TRUE(sample_light(l, refs[i], vec2(0.3f, 0.6f), LightSampling::solid_angle, ls));
    EXPECT_FLOAT_EQ(ls.pdf, 1.0f / st.solid_angle);
    auto r = tri_chi_square(l, refs[i], LightSampling::solid_angle, 25 + i);
    EXPECT_GT(r.p_value, kAlpha) << "ref " << i << " " << r.describe();
    EXPECT_NEAR(r.expected_total / 400000, 1.0, 2e-3) << "ref " << i;
  }
}

TEST(LightSampling, TrianglesOutsideTheSolidAngleRangeAreSampledByArea) {
  // 1.5e-4 sr, below the 3e-4 sr floor: the pdf is the area one, and sample_light's points still follow it.
  Light l = make_triangle_light(vec3(-0.5f, 1, -0.5f), vec3(0.5f, 1, -0.5f), vec3(0, 1, 0.7f), vec3(1));
  vec3 ref(10.0f, -60.0f, 5.0f);
  SphericalTriangle st;
  ASSERT_TRUE(make_spherical_triangle(ref, l.p0, l.e1, l.e2, st));
  ASSERT_LT(st.solid_angle, 3e-4f);
  LightSample ls;
  ASSERT_TRUE(sample_light(l, ref, vec2(0.3f, 0.6f), LightSampling::solid_angle, ls));
  EXPECT_NEAR(ls.pdf, ls.dist * ls.dist / (l.area * -glm::dot(ls.wi, l.n)), 1e-3f * ls.pdf);
  auto r = tri_chi_square(l, ref, LightSampling::solid_angle, 28);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
  EXPECT_NEAR(r.expected_total / 400000, 1.0, 2e-3);
}

TEST(LightSampling, TriangleAreaDensitySpreadIsTheDistanceRatioCubed) {
  // Against a brute force over points of the triangle (barycentric grid, plus its vertices and edges): the largest
  // over the smallest distance, cubed. Receivers nearest to each vertex, each edge and the interior, and off-plane.
  Light l = make_triangle_light(vec3(-0.5f, 1, -0.5f), vec3(0.5f, 1, -0.5f), vec3(0, 1, 0.7f), vec3(1));
  const vec3 refs[] = {vec3(-1, 0.5f, -1), vec3(1, 0.2f, -1), vec3(0, 0.7f, 1.5f), vec3(0, 0.9f, -1),
                       vec3(0.6f, 0.5f, 0.4f), vec3(-0.6f, 0.5f, 0.4f), vec3(0.05f, 0.8f, 0.0f), vec3(0.1f, -3, 0.2f)};
  const int n = 400;
  for (vec3 ref : refs) {
    double r_min = 1e30, r_max = 0.0;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        dvec3 p = dvec3(l.p0) + (double(i) / n) * dvec3(l.e1) + (double(j) / n) * dvec3(l.e2);
        double r = glm::length(p - dvec3(ref));
        r_min = std::min(r_min, r);
        r_max = std::max(r_max, r);
      }
    double expected = std::pow(r_max / r_min, 3.0);
    EXPECT_NEAR(triangle_area_density_spread(l, ref), expected, 2e-3 * expected)
        << ref.x << "," << ref.y << "," << ref.z;
  }
}

TEST(LightSampling, SphereConeSamplingIsUniformInSolidAngle) {
  for (float dist : {1.5f, 40.0f}) {  // a wide cap, and a narrow one that takes the small-angle branch
    Light l = make_sphere_light(vec3(0, dist, 0), 0.5f, vec3(1));
    vec3 ref(0.0f);
    Frame f = Frame::from_normal(vec3(0, 1, 0));
    double sin2_max = 0.25 / (double(dist) * dist);
    double one_minus_cos_max = 1.0 - std::sqrt(1.0 - sin2_max);
    auto r = test::chi_square_2d(
        [&](vec2 u) {
          LightSample ls;
          if (!sample_light(l, ref, u, LightSampling::solid_angle, ls)) return vec2(-1.0f);
          EXPECT_NEAR(ls.pdf, 1.0 / (2.0 * M_PI * one_minus_cos_max), 2e-3 / one_minus_cos_max);
          EXPECT_NEAR(glm::length(ls.point.p - l.p0), 0.5f, 1e-4f * dist);
          vec3 d = f.to_local(ls.wi);
          double one_minus_cos = double(d.x * d.x + d.y * d.y) / (1.0 + d.z);
          float phi = std::atan2(d.y, d.x);
          if (phi < 0) phi += 2.0f * float(M_PI);
          return vec2(float(std::min(one_minus_cos / one_minus_cos_max, 0.999999)), phi / (2.0f * float(M_PI)));
        },
        [](vec2) { return 1.0; }, 16, 16, 300000, 22);
    EXPECT_GT(r.p_value, kAlpha) << "dist " << dist << " " << r.describe();
  }
}

/// Checks LightSampling::automatic's choice for light `l` (facing -y at y = 1) against a brute-force spread.
void check_automatic_choice(const Light& l) {
  const bool tri = l.kind == LightKind::triangle;
  auto spread = [&](vec3 ref) {
    double lo = 1e300, hi = 0.0;
    for (int i = 0; i <= 64; ++i)
      for (int j = 0; j <= (tri ? 64 - i : 64); ++j) {
        dvec3 p = dvec3(l.p0) + (i / 64.0) * dvec3(l.e1) + (j / 64.0) * dvec3(l.e2);
        dvec3 d = dvec3(ref) - p;
        double r = glm::length(d), density = glm::dot(d, dvec3(l.n)) / (r * r * r);  // cos_l / r^2
        lo = std::min(lo, density);
        hi = std::max(hi, density);
      }
    return hi / lo;
  };
  Pcg32 rng(11, 12);
  for (float threshold : {kAutoMinSpread, kAutoMinSpreadDeep}) {
    int solid = 0, area = 0;
    for (int k = 0; k < 3000; ++k) {
      const float w = k % 2 ? 16.0f : 3.0f, h = k % 2 ? 7.0f : 1.0f;
      vec3 ref = vec3(-0.5f * w, 0.95f - h, -0.5f * w) + vec3(w * rng.next_float(), h * rng.next_float(), w * rng.next_float());
      LightSample ls[2];
      bool ok = true;
      for (LightSample& s : ls) {
        ok = ok && sample_light(l, ref, vec2(rng.next_float(), rng.next_float()), LightSampling::automatic, s, threshold);
        if (ok) {
          ASSERT_NEAR(light_pdf(l, ref, s.wi, s.dist, l.n, LightSampling::automatic, threshold), s.pdf, 2e-3f * s.pdf);
        }
      }
      if (!ok) continue;
      float solid_angle = 0.0f;
      if (tri) {
        SphericalTriangle st;
        ASSERT_TRUE(make_spherical_triangle(ref, l.p0, l.e1, l.e2, st));
        solid_angle = st.solid_angle;
      } else if (!l.rectangular) {
        SphericalParallelogram sp;
        ASSERT_TRUE(make_spherical_parallelogram(ref, l.p0, l.e1, l.e2, sp));
        solid_angle = sp.solid_angle;
      } else {
        SphericalRectangle sr;
        ASSERT_TRUE(make_spherical_rectangle(ref, l.p0, l.e1, l.e2, sr));
        solid_angle = sr.solid_angle;
      }
      // Outside the usable range every mode samples by area, whatever the spread.
      if (solid_angle < kMinSolidAngle || solid_angle > kMaxSolidAngle) continue;
      const bool took_solid_angle =
          std::abs(ls[0].pdf * solid_angle - 1.0f) < 1e-3f && std::abs(ls[1].pdf * solid_angle - 1.0f) < 1e-3f;
      const double s = spread(ref);
      if (std::abs(s / threshold - 1.0) < 0.02) continue;  // too close to call with a 64 x 64 grid
      ASSERT_EQ(took_solid_angle, s >= threshold) << (tri ? "triangle" : l.rectangular ? "rectangle" : "parallelogram") << " spread " << s
                                                  << " threshold " << threshold << " at " << ref.x << "," << ref.y
                                                  << "," << ref.z;
      (took_solid_angle ? solid : area)++;
    }
    EXPECT_GE(solid, 200) << threshold << (tri ? " triangle" : " rectangle");
    EXPECT_GE(area, 200) << threshold << (tri ? " triangle" : " rectangle");
  }
}

// LightSampling::automatic takes the spherical rectangle or triangle exactly where area sampling's solid-angle
// density spreads by at least the asked factor over the light (light.h, kAutoMinSpread): the spread is recomputed
// here by brute force in double over a grid on the light, and which sampling was taken is read off the returned
// pdfs (the spherical one's is 1 / solid angle for every sample; two samples of area sampling at different points almost
// never both equal it). Reference points come from a box near the light and a wide one; both sides of the switch
// must be seen, at both thresholds.
TEST(LightSampling, AutomaticTakesSolidAngleWhereTheAreaDensitySpreads) {
  for (const Light& l : {make_rect_light(vec3(-0.5f, 1, -0.4f), vec3(1, 0, 0), vec3(0, 0, 0.8f), vec3(1)),
                         make_rect_light(vec3(-0.5f, 1, -0.4f), vec3(0.8f, 0, 0), vec3(0.3f, 0, 0.8f), vec3(1)),
                         make_triangle_light(vec3(-0.5f, 1, -0.4f), vec3(0.5f, 1, -0.4f), vec3(-0.2f, 1, 0.5f), vec3(1))})
    check_automatic_choice(l);
}

TEST(LightSampling, PlanarSamplesBoundTheirDistanceFromTheLightsPlane) {
  // A sampled point is rounded off the light's plane; the shadow ray's end is offset by its p_error, so that bound
  // must cover the rounding (else the shadow ray may start behind the light and hit it). Far from the origin a point
  // is almost never exactly on the plane, so a bound of zero, or one built from the wrong magnitudes, fails here.
  const vec3 far(1.3e4f, -2.7e3f, 6.1e3f);
  const Light lights[] = {
      make_rect_light(far, vec3(3.1f, 0.2f, 0.7f), vec3(-0.2f, 3.1f, 0.0f), vec3(1.0f)),  // a tilted rectangle
      make_rect_light(far, vec3(2.0f, 0.0f, 0.3f), vec3(1.1f, 1.7f, 0.0f), vec3(1.0f)),   // sheared
      make_triangle_light(far, far + vec3(2.5f, 0.4f, 0.1f), far + vec3(0.3f, 2.2f, 0.2f), vec3(1.0f))};
  ASSERT_TRUE(lights[0].rectangular);
  ASSERT_FALSE(lights[1].rectangular);
  Pcg32 rng(21, 5);
  for (const Light& l : lights) {
    const glm::dvec3 n = glm::normalize(glm::cross(glm::dvec3(l.e1), glm::dvec3(l.e2)));
    const vec3 ref = l.p0 + 0.4f * l.e1 + 0.3f * l.e2 + 1.5f * l.n;  // near: solid angle is used
    int off_plane = 0;
    for (LightSampling mode : {LightSampling::area, LightSampling::solid_angle}) {
      for (int i = 0; i < 4000; ++i) {
        LightSample ls;
        if (!sample_light(l, ref, vec2(rng.next_float(), rng.next_float()), mode, ls)) continue;
        const double dist = std::abs(glm::dot(glm::dvec3(ls.point.p) - glm::dvec3(l.p0), n));
        const double bound = glm::dot(glm::abs(n), glm::dvec3(ls.point.p_error));
        off_plane += dist > 0.0;
        ASSERT_LE(dist, bound) << "light kind " << int(l.kind) << ", sample " << i;
      }
    }
    EXPECT_GT(off_plane, 1000) << "the test needs points rounded off the plane";
  }
}

// A sphere light's sampled point is rounded off the sphere (the direction's sines and cosines, the product with the
// radius, the sum with the centre); the shadow ray's end is offset by its p_error, so that bound must reach the
// sphere. A large sphere near the origin and one far from it: a bound built from the centre alone, or from one
// rounding, fails at one of them.
TEST(LightSampling, SphereSamplesBoundTheirDistanceFromTheSphere) {
  const Light lights[] = {make_sphere_light(vec3(0.5f, -0.3f, 0.2f), 3.0e3f, vec3(1.0f)),
                          make_sphere_light(vec3(1.3e4f, -2.7e3f, 6.1e3f), 2.5f, vec3(1.0f))};
  Pcg32 rng(23, 9);
  for (const Light& l : lights) {
    const glm::dvec3 c(l.p0);
    int off_sphere = 0;
    for (float distance : {1.05f, 1.5f, 40.0f}) {  // a wide cone, a middle one, and a small one
      const vec3 ref = l.p0 + distance * l.radius * glm::normalize(vec3(0.3f, 0.8f, -0.5f));
      for (int i = 0; i < 4000; ++i) {
        LightSample ls;
        if (!sample_light(l, ref, vec2(rng.next_float(), rng.next_float()), LightSampling::solid_angle, ls)) continue;
        const double dist = std::abs(glm::length(glm::dvec3(ls.point.p) - c) - double(l.radius));
        off_sphere += dist > 0.0;
        ASSERT_LE(dist, glm::length(glm::dvec3(ls.point.p_error))) << "radius " << l.radius << ", sample " << i;
      }
    }
    EXPECT_GT(off_sphere, 1000) << "the test needs points rounded off the sphere";
  }
}

// A light's share of the light choice is its power, pi * luminance * area: lights of one luminance weigh the same
// whatever their colour, and a dimmer colour less.
TEST(LightSampling, LightPowerIsPiTimesLuminanceTimesArea) {
  const vec3 corner(0.0f), e1(2.0f, 0.0f, 0.0f), e2(0.0f, 0.0f, 1.5f);
  const float area = 3.0f;
  for (vec3 emission : {vec3(2.0f), vec3(2.0f / 0.2126f, 0.0f, 0.0f), vec3(0.0f, 2.0f / 0.7152f, 0.0f),
                        vec3(0.0f, 0.0f, 2.0f / 0.0722f)}) {
    EXPECT_NEAR(light_power(make_rect_light(corner, e1, e2, emission)), kPi * 2.0f * area, 1e-4f)
        << emission.x << "," << emission.y << "," << emission.z;
  }
  EXPECT_NEAR(light_power(make_rect_light(corner, e1, e2, vec3(1.0f, 0.0f, 0.0f))), kPi * 0.2126f * area, 1e-5f);
  EXPECT_EQ(light_power(make_rect_light(corner, e1, e2, vec3(-1.0f))), 0.0f);
}

TEST(LightSampling, BackSideAndBehindGiveNothing) {
  Light rect = make_rect_light(vec3(0, 1, 0), vec3(0, 0, 1), vec3(1, 0, 0), vec3(1));  // faces +y
  LightSample ls;
  EXPECT_FALSE(sample_light(rect, vec3(0.5f, 0.0f, 0.5f), vec2(0.5f), LightSampling::solid_angle, ls));
  EXPECT_EQ(light_pdf(rect, vec3(0.5f, 0.0f, 0.5f), vec3(0, 1, 0), 1.0f, rect.n, LightSampling::solid_angle), 0.0f);
  EXPECT_TRUE(sample_light(rect, vec3(0.5f, 2.0f, 0.5f), vec2(0.5f), LightSampling::solid_angle, ls));
  Light sphere = make_sphere_light(vec3(0), 1.0f, vec3(1));
  EXPECT_FALSE(sample_light(sphere, vec3(0.2f, 0, 0), vec2(0.5f), LightSampling::solid_angle, ls));  // inside
}

bool below(const Light& l, vec3 p, vec3 n) { return light_below_plane(l, std::span<const vec3>(&p, 1), n); }

/// light_below_plane is what lets the integrator skip light samples (RenderScene::tri_unlit_sides): wherever it says
/// a light is below a triangle's plane, no sample_light direction from a point of the triangle, in any mode, may
/// come out above it by the test eval_bsdf_cos makes (dot(wi, n) <= 0). And it must say so for a plane well above
/// the light, and not for one that cuts or touches it.
TEST(LightSampling, LightBelowPlaneOnlyWhereNoSampleRisesAboveIt) {
  const Light lights[] = {make_rect_light(vec3(-0.5f, 1, -0.4f), vec3(1, 0, 0), vec3(0, 0, 0.8f), vec3(1)),
                          make_rect_light(vec3(-0.5f, 1, -0.4f), vec3(0.8f, 0, 0), vec3(0.3f, 0, 0.8f), vec3(1)),
                          make_triangle_light(vec3(-0.5f, 1, -0.4f), vec3(0.5f, 1, -0.4f), vec3(-0.2f, 1, 0.5f), vec3(1)),
                          make_sphere_light(vec3(0.2f, 1, 0.1f), 0.3f, vec3(1))};
  for (const Light& l : lights) {
    // Every light here lies within y in [0.7, 1.3].
    EXPECT_TRUE(below(l, vec3(0.3f, 3, -0.2f), vec3(0, 1, 0)));                // well above it
    EXPECT_FALSE(below(l, vec3(0.3f, 3, -0.2f), vec3(0, -1, 0)));              // the other side
    EXPECT_FALSE(below(l, vec3(0.3f, -3, -0.2f), vec3(0, 1, 0)));              // below it
    EXPECT_FALSE(below(l, l.p0, vec3(1, 0, 0)));                               // the plane cuts or touches it
    EXPECT_FALSE(below(l, l.p0 + vec3(0, l.radius, 0), vec3(0, 1, 0)));        // touches it from above
    const vec3 tri[3] = {vec3(0, 3, 0), vec3(1, 3, 0), vec3(0, 1.0f, 1)};       // a tilted plane, the light above it
    EXPECT_FALSE(light_below_plane(l, tri, glm::normalize(glm::cross(tri[1] - tri[0], tri[2] - tri[0]))));
  }
  Pcg32 rng = make_sample_rng(7, 0, 0);
  auto uniform = [&] { return rng.next_float(); };
  int below_count = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Light& l = lights[size_t(trial) % 4];
    const Frame f = Frame::from_normal(sample_uniform_sphere(vec2(uniform(), uniform())));
    // Half the triangles anywhere, half with a corner just above the light's corner (sphere: center), 1e-6 to 1
    // away: near the margin.
    const vec3 c = trial % 8 < 4 ? vec3(4.0f * uniform() - 2.0f, 3.0f * uniform(), 4.0f * uniform() - 2.0f)
                                 : l.p0 + (l.radius + std::pow(10.0f, -6.0f * uniform())) * f.n;
    const vec3 tri[3] = {c, c + (uniform() - 0.5f) * f.s + (uniform() - 0.5f) * f.t,
                         c + (uniform() - 0.5f) * f.s + (uniform() - 0.5f) * f.t};
    const vec3 n = f.n;
    if (!light_below_plane(l, tri, n)) continue;
    ++below_count;
    for (LightSampling mode : {LightSampling::area, LightSampling::solid_angle, LightSampling::automatic})
      for (int i = 0; i < 64; ++i) {
        const vec3 b = sample_uniform_triangle(vec2(uniform(), uniform()));
        const vec3 p = b.x * tri[0] + b.y * tri[1] + b.z * tri[2];
        LightSample ls;
        if (sample_light(l, p, vec2(uniform(), uniform()), mode, ls)) {
          ASSERT_LE(glm::dot(ls.wi, n), 0.0f) << "trial " << trial;
        }
      }
  }
  EXPECT_GT(below_count, 500);
}

}  // namespace
}  // namespace pt
