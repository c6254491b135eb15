// Every sampling routine against its claimed density (chi-square), densities that integrate to 1, and frames
// that stay orthonormal everywhere.
#include <gtest/gtest.h>

#include <limits>

#include "chi_square.h"
#include "core/frame.h"
#include "core/sampling.h"

namespace pt {
namespace {

using test::chi_square_2d;

// 21 chi-square p-values below (cosine hemisphere, sphere, triangle, 7 spherical rectangles, 9 spherical
// triangles, 2 in the discrete distribution); a Sidak-corrected significance level keeps the family's false alarm
// rate at 1%.
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / 21.0);
const int kSamples = 1000000;

float wrap_phi(vec3 d) {
  float phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += kTwoPi;
  return std::min(phi * kInv2Pi, kOneMinusEpsilon);
}

TEST(Sampling, CosineHemisphereFollowsItsPdf) {
  // Parametrize by (cos theta, phi / 2 pi): d omega = d cos d phi, so the density is pdf(omega) * 2 pi.
  auto r = chi_square_2d([](vec2 u) { vec3 d = sample_cosine_hemisphere(u); return vec2(d.z, wrap_phi(d)); },
                         [](vec2 x) { return cosine_hemisphere_pdf(x.x) * kTwoPi; }, 20, 40, kSamples, 1);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
  EXPECT_NEAR(r.expected_total / kSamples, 1.0, 1e-3);
}

TEST(Sampling, ConcentricDiskIsShirleyChiusMap) {
  // The map itself, not only its density: the branchless form with the polynomial sine and cosine lands within a
  // few ulps of Shirley and Chiu's two-case formula in double at every point of a grid over the square (strata of
  // u must stay the same regions of the disk for the Sobol sampler's stratification to carry over).
  double worst = 0.0;
  const int n = 601;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const vec2 u(float(i) / float(n), float(j) / float(n));
      const double a = 2.0 * u.x - 1.0, b = 2.0 * u.y - 1.0;
      double x = 0.0, y = 0.0;
      if (a != 0.0 || b != 0.0) {
        const bool x_major = std::abs(a) > std::abs(b);
        const double r = x_major ? a : b, theta = x_major ? M_PI / 4 * (b / a) : M_PI / 2 - M_PI / 4 * (a / b);
        x = r * std::cos(theta);
        y = r * std::sin(theta);
      }
      const vec2 p = sample_uniform_disk_concentric(u);
      worst = std::max({worst, std::abs(p.x - x), std::abs(p.y - y)});
      ASSERT_LE(double(p.x) * p.x + double(p.y) * p.y, 1.0 + 1e-6) << u.x << " " << u.y;
      // Malley's lift of the same point: a unit vector in the upper hemisphere (z comes from the radius).
      const vec3 d = sample_cosine_hemisphere(u);
      ASSERT_EQ(d.x, p.x);
      ASSERT_EQ(d.y, p.y);
      ASSERT_GE(d.z, 0.0f);
      ASSERT_NEAR(glm::length(dvec3(d)), 1.0, 1e-6) << u.x << " " << u.y;
    }
  EXPECT_LT(worst, 5e-7);
}

TEST(Sampling, UniformSphereFollowsItsPdf) {
  auto r = chi_square_2d([](vec2 u) { vec3 d = sample_uniform_sphere(u); return vec2(0.5f * (d.z + 1.0f), wrap_phi(d)); },
                         [](vec2) { return uniform_sphere_pdf() * 2.0 * kTwoPi; }, 20, 40, kSamples, 2);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
  EXPECT_NEAR(r.expected_total / kSamples, 1.0, 1e-3);
}

TEST(Sampling, TriangleIsUniformByArea) {
  // Through the inverse of the classic square-root warp, (b0, b1, b2) -> ((1 - b0)^2, b1 / (1 - b0)), a point
  // uniform by area becomes uniform on the unit square.
  auto r = chi_square_2d(
      [](vec2 u) {
        vec3 b = sample_uniform_triangle(u);
        double s = 1.0 - double(b.x);
        return vec2(float(s * s), s > 0 ? float(double(b.y) / s) : 0.0f);
      },
      [](vec2) { return 1.0; }, 24, 24, kSamples, 4);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
  for (int i = 0; i < 1000; ++i) {
    vec3 b = sample_uniform_triangle(vec2(i / 1000.0f, std::fmod(i * 0.618034f, 1.0f)));
    EXPECT_NEAR(b.x + b.y + b.z, 1.0f, 1e-6f);
    EXPECT_GE(min_component(b), 0.0f);
  }
}

struct RectCase {
  vec3 ref, corner, e1, e2;
};

class SphericalRectTest : public ::testing::TestWithParam<int> {};

const RectCase kRects[] = {
    {vec3(0.1f, -1.0f, 0.2f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1)},         // below the center
    {vec3(3.0f, -0.5f, 1.0f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1)},         // far to the side
    {vec3(-0.45f, -0.05f, -0.48f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1)},    // close to a corner
    {vec3(0.2f, 0.7f, 0.1f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1)},          // above the plane
    {vec3(0.3f, 0.2f, 1.5f), vec3(0, 0, 0), vec3(0.6f, 0.8f, 0), vec3(-0.4f, 0.3f, 0.5f)},   // tilted, long-short
    {vec3(2.5f, -0.012f, 0.1f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1)},       // grazing: 8e-4 sr
    {vec3(30.0f, -40.0f, 20.0f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1)},      // tiny: ~3.7e-4 sr
};

TEST_P(SphericalRectTest, UniformInSolidAngle) {
  const RectCase c = kRects[GetParam()];
  SphericalRectangle sr;
  ASSERT_TRUE(make_spherical_rectangle(c.ref, c.corner, c.e1, c.e2, sr));
  const vec3 n = glm::normalize(glm::cross(c.e1, c.e2));
  const double area = glm::length(glm::cross(c.e1, c.e2));
  const float l1 = glm::length(c.e1), l2 = glm::length(c.e2);
  // Density over the rectangle's (a, b) parameters: (1 / solid angle) * d omega / d(a, b).
  auto density = [&](vec2 x) {
    vec3 p = c.corner + x.x * c.e1 + x.y * c.e2;
    vec3 d = p - c.ref;
    double dist2 = glm::dot(d, d);
    double cos_l = std::abs(glm::dot(glm::normalize(d), n));
    return cos_l * area / dist2 / sr.solid_angle;
  };
  auto sample = [&](vec2 u) {
    vec3 p = sample_spherical_rectangle(sr, u) - c.corner;
    return vec2(glm::dot(p, c.e1) / (l1 * l1), glm::dot(p, c.e2) / (l2 * l2));
  };
  auto r = chi_square_2d(sample, density, 24, 24, kSamples, 10 + GetParam());
  EXPECT_GT(r.p_value, kAlpha) << "case " << GetParam() << " " << r.describe();
  // The solid angle itself: the density integrates to 1 only if solid_angle is right.
  EXPECT_NEAR(r.expected_total / kSamples, 1.0, 2e-3) << "case " << GetParam();
}
INSTANTIATE_TEST_SUITE_P(Rects, SphericalRectTest, ::testing::Range(0, 7));

TEST(Sampling, SphericalRectangleDegenerateCases) {
  SphericalRectangle sr;
  EXPECT_FALSE(make_spherical_rectangle(vec3(0.2f, 0, 0.3f), vec3(0), vec3(1, 0, 0), vec3(0, 0, 1), sr));  // in plane
  EXPECT_EQ(sr.solid_angle, 0.0f);
  EXPECT_FALSE(make_spherical_rectangle(vec3(0, 1, 0), vec3(0), vec3(0, 0, 0), vec3(0, 0, 1), sr));  // no area
  // Sampled points stay on the rectangle even for far, thin configurations.
  ASSERT_TRUE(make_spherical_rectangle(vec3(0, 1e3f, 0), vec3(0), vec3(1e-3f, 0, 0), vec3(0, 0, 1), sr));
  Pcg32 rng(1, 1);
  for (int i = 0; i < 10000; ++i) {
    vec3 p = sample_spherical_rectangle(sr, vec2(rng.next_float(), rng.next_float()));
    ASSERT_TRUE(is_finite(p));
    EXPECT_GE(p.x, -1e-6f);
    EXPECT_LE(p.x, 1e-3f + 1e-6f);
    EXPECT_NEAR(p.y, 0.0f, 1e-3f);
  }
}

TEST(Sampling, SphericalRectangleSamplesStayOnTheRectangleAtTheEnds) {
  // The ends of u (0 and 1 - eps) and receivers just off the plane, above the rectangle or grazing it from afar: the
  // inversions there put x at +-inf (a quotient by a vanishing difference) or y an ulp or two past its edge, and
  // the clamps bring them back. The sample is on the unit square of the plane y = 0, to within two roundings of the
  // point's own coordinates.
  Pcg32 rng(5, 5);
  const float us[] = {0.0f, 1e-7f, 0.5f, 1.0f - 1e-6f, kOneMinusEpsilon};
  for (int i = 0; i < 40000; ++i) {
    const float a = rng.next_float(), b = rng.next_float(), c = rng.next_float();
    vec3 ref;
    switch (i % 4) {
      case 0: ref = vec3(4 * a - 2, -(0.01f + 2 * b), 4 * c - 2); break;
      case 1: ref = vec3(4 * a - 2, -std::ldexp(1.0f, -int(20 * b) - 1), 4 * c - 2); break;  // just off the plane
      case 2: ref = vec3(40 * a - 20, -std::ldexp(1.0f, -int(10 * b)), 40 * c - 20); break;  // grazing, far
      default: ref = vec3(a, -std::ldexp(1.0f, -int(24 * b)), c); break;                     // above it, close
    }
    SphericalRectangle sr;
    if (!make_spherical_rectangle(ref, vec3(0), vec3(1, 0, 0), vec3(0, 0, 1), sr)) continue;
    const double tol = 0x1p-23 * std::max({1.0f, std::abs(ref.x), std::abs(ref.z)});
    for (float ux : us) {
      for (float uy : us) {
        const vec3 p = sample_spherical_rectangle(sr, vec2(ux, uy));
        ASSERT_TRUE(is_finite(p)) << ref.x << " " << ref.y << " " << ref.z << " u " << ux << " " << uy;
        ASSERT_GE(p.x, -tol) << ref.x << " " << ref.y << " " << ref.z << " u " << ux << " " << uy;
        ASSERT_LE(p.x, 1.0 + tol) << ref.x << " " << ref.y << " " << ref.z << " u " << ux << " " << uy;
        ASSERT_GE(p.z, -tol) << ref.x << " " << ref.y << " " << ref.z << " u " << ux << " " << uy;
        ASSERT_LE(p.z, 1.0 + tol) << ref.x << " " << ref.y << " " << ref.z << " u " << ux << " " << uy;
      }
    }
  }
}

TEST(Sampling, SphericalRectangleIsTheSameAtAnyScale) {
  // Scaling the receiver and the rectangle by 2^k changes no angle: the solid angle is the same and the samples scale
  // with it, to a few roundings. At 2^+-60 a product of four lengths (the corner angles' complex products) is 2^+-240,
  // beyond float's range: the setup rescales the lengths first.
  const RectCase c = kRects[4];  // tilted, long-short
  SphericalRectangle base;
  ASSERT_TRUE(make_spherical_rectangle(c.ref, c.corner, c.e1, c.e2, base));
  for (int k : {-60, -40, 40, 60}) {
    const float s = std::ldexp(1.0f, k);
    SphericalRectangle sr;
    ASSERT_TRUE(make_spherical_rectangle(s * c.ref, s * c.corner, s * c.e1, s * c.e2, sr)) << k;
    EXPECT_NEAR(sr.solid_angle, base.solid_angle, 1e-6f * base.solid_angle) << k;
    for (vec2 u : {vec2(0.1f, 0.2f), vec2(0.5f, 0.5f), vec2(0.9f, 0.3f), vec2(0.0f, kOneMinusEpsilon)}) {
      const vec3 expected = sample_spherical_rectangle(base, u), got = sample_spherical_rectangle(sr, u) / s;
      EXPECT_LE(glm::length(got - expected), 1e-5f) << k << " u " << u.x << " " << u.y;
    }
  }
}

struct TriCase {
  vec3 ref, p0, e1, e2;
};

class SphericalTriTest : public ::testing::TestWithParam<int> {};

const TriCase kTris[] = {
    {vec3(0.1f, -1.0f, 0.2f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0.2f, 0, 1)},           // below: 0.36 sr
    {vec3(3.0f, -0.5f, 1.0f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0.2f, 0, 1)},           // far to the side
    {vec3(0.42f, -0.05f, -0.45f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0.2f, 0, 1)},       // near a corner: 2.9 sr
    {vec3(0.3f, 0.2f, 1.5f), vec3(0, 0, 0), vec3(0.6f, 0.8f, 0), vec3(-0.4f, 0.3f, 0.5f)},       // tilted
    {vec3(2.5f, -0.012f, 0.1f), vec3(-0.5f, 0, -0.5f), vec3(1, 0, 0), vec3(0.2f, 0, 1)},         // grazing: 3.5e-4 sr
    {vec3(30.0f, -40.0f, 20.0f), vec3(-0.5f, 0, -0.5f), vec3(1.6f, 0, 0), vec3(0.2f, 0, 1.6f)},  // tiny: 3.3e-4 sr
    {vec3(0.2f, -0.3f, 0.1f), vec3(-3, 0, -3), vec3(8, 0, 0), vec3(0, 0, 8)},                    // large: 5.5 sr
    {vec3(1.0f, -0.3f, 0.5f), vec3(0, 0, 0), vec3(3, 0, 0), vec3(1.5f, 0, 0.05f)},               // thin, sharp at p0
    {vec3(0.1f, -0.03f, 0.02f), vec3(0, 0, 0), vec3(-1.5f, 0, 0.05f), vec3(1.5f, 0, 0.05f)},     // obtuse at p0, close
};

/// The solid angle in double: Van Oosterom and Strackee's formula with plain dot products (exact enough in double).
double solid_angle_double(const TriCase& c) {
  const dvec3 pa = dvec3(c.p0) - dvec3(c.ref), pb = pa + dvec3(c.e1), pc = pa + dvec3(c.e2);
  const dvec3 a = glm::normalize(pa), b = glm::normalize(pb), cc = glm::normalize(pc);
  return 2.0 * std::atan2(std::abs(glm::dot(a, glm::cross(b, cc))),
                          1.0 + glm::dot(a, b) + glm::dot(b, cc) + glm::dot(cc, a));
}

TEST_P(SphericalTriTest, UniformInSolidAngle) {
  const TriCase c = kTris[GetParam()];
  SphericalTriangle st;
  ASSERT_TRUE(make_spherical_triangle(c.ref, c.p0, c.e1, c.e2, st));
  const double omega = solid_angle_double(c);
  EXPECT_NEAR(st.solid_angle, omega, 1e-5 * omega) << "case " << GetParam();
  const dvec3 p0(c.p0), e1(c.e1), e2(c.e2), ref(c.ref);
  const dvec3 nn = glm::cross(e1, e2);
  const double area = 0.5 * glm::length(nn);
  const dvec3 n = nn / glm::length(nn);
  // Points of the triangle are parametrized by (x, y) in [0,1]^2 through the inverse square-root warp
  // (b1 + b2 = sqrt(x), b1 = sqrt(x) y), uniform by area, so the density over (x, y) is
  // (1 / solid angle) * d omega / dA * area.
  auto density = [&](vec2 x) {
    const double s = std::sqrt(double(x.x));
    const dvec3 d = p0 + s * double(x.y) * e1 + s * (1.0 - double(x.y)) * e2 - ref;
    const double dist2 = glm::dot(d, d);
    return std::abs(glm::dot(d, n)) / std::sqrt(dist2) * area / dist2 / st.solid_angle;
  };
  // The barycentrics of a point from the Gram system of the edges, in double.
  const double g11 = glm::dot(e1, e1), g12 = glm::dot(e1, e2), g22 = glm::dot(e2, e2), det = g11 * g22 - g12 * g12;
  double max_off_plane = 0.0;
  auto sample = [&](vec2 u) {
    const dvec3 q = dvec3(sample_spherical_triangle(st, u)) - p0;
    max_off_plane = std::max(max_off_plane, std::abs(glm::dot(q, n)));
    const double r1 = glm::dot(q, e1), r2 = glm::dot(q, e2);
    const double b1 = (g22 * r1 - g12 * r2) / det, b2 = (g11 * r2 - g12 * r1) / det;
    const double s = b1 + b2;
    return vec2(float(s * s), s > 0.0 ? float(b1 / s) : 0.0f);
  };
  auto r = chi_square_2d(sample, density, 24, 24, kSamples, 40 + GetParam());
  EXPECT_GT(r.p_value, kAlpha) << "case " << GetParam() << " " << r.describe();
  // The density integrates to 1 only if solid_angle is right (an independent check of the formula).
  EXPECT_NEAR(r.expected_total / kSamples, 1.0, 2e-3) << "case " << GetParam();
  const double size = glm::length(e1) + glm::length(e2) + glm::length(p0 - ref);
  EXPECT_LE(max_off_plane, 1e-6 * size) << "case " << GetParam();
}
INSTANTIATE_TEST_SUITE_P(Tris, SphericalTriTest, ::testing::Range(0, 9));

TEST(Sampling, SphericalTriangleDegenerateCases) {
  SphericalTriangle st;
  EXPECT_FALSE(make_spherical_triangle(vec3(0.2f, 0, 0.3f), vec3(0), vec3(1, 0, 0), vec3(0, 0, 1), st));  // in plane
  EXPECT_EQ(st.solid_angle, 0.0f);
  EXPECT_FALSE(make_spherical_triangle(vec3(0, 1, 0), vec3(0), vec3(0, 0, 0), vec3(0, 0, 1), st));  // no area
  EXPECT_FALSE(make_spherical_triangle(vec3(0, 1, 0), vec3(0), vec3(1, 0, 0), vec3(2, 0, 0), st));  // collinear
  EXPECT_FALSE(make_spherical_triangle(vec3(0), vec3(0), vec3(1, 0, 0), vec3(0, 0, 1), st));  // ref at a vertex
  // Sampled points stay on the triangle even for far, thin configurations, and for u at the corners of [0,1]^2.
  ASSERT_TRUE(make_spherical_triangle(vec3(0, 1e3f, 0), vec3(0), vec3(1e-3f, 0, 0), vec3(0, 0, 1), st));
  Pcg32 rng(1, 1);
  for (int i = 0; i < 10000; ++i) {
    vec2 u = i < 4 ? vec2(float(i & 1), float(i >> 1)) : vec2(rng.next_float(), rng.next_float());
    vec3 p = sample_spherical_triangle(st, u);
    ASSERT_TRUE(is_finite(p));
    EXPECT_GE(p.x, -1e-6f);
    EXPECT_GE(p.z, -1e-6f);
    EXPECT_LE(p.x * 1e3f + p.z, 1.0f + 1e-5f);
    EXPECT_NEAR(p.y, 0.0f, 1e-6f);
  }
}

TEST(Sampling, DiscreteDistributionFollowsWeights) {
  const std::vector<float> w = {1.0f, 0.0f, 3.0f, 0.5f, 0.0f, 2.5f};
  DiscreteDistribution d(w);
  std::vector<double> counts(w.size(), 0.0), remapped(10, 0.0);
  Pcg32 rng(7, 7);
  const int n = 700000;
  for (int i = 0; i < n; ++i) {
    float pmf, ur;
    size_t k = d.sample(rng.next_float(), &pmf, &ur);
    ASSERT_GT(w[k], 0.0f) << "picked a zero-weight entry";
    EXPECT_EQ(pmf, d.pmf(k));
    counts[k] += 1;
    remapped[std::min(size_t(ur * 10), size_t(9))] += 1;
  }
  double chi2 = 0.0, chi2_u = 0.0, total = 7.0;
  int dof = -1;
  for (size_t k = 0; k < w.size(); ++k) {
    if (w[k] == 0.0f) continue;
    double e = n * w[k] / total;
    chi2 += (counts[k] - e) * (counts[k] - e) / e;
    ++dof;
  }
  for (double c : remapped) chi2_u += (c - n / 10.0) * (c - n / 10.0) / (n / 10.0);
  EXPECT_GT(test::gamma_q(0.5 * dof, 0.5 * chi2), kAlpha) << chi2;
  EXPECT_GT(test::gamma_q(4.5, 0.5 * chi2_u), kAlpha) << chi2_u;  // the remapped u is uniform
  double sum = 0.0;
  for (size_t k = 0; k < d.size(); ++k) sum += d.pmf(k);
  EXPECT_NEAR(sum, 1.0, 1e-6);
  // All zero weights: uniform.
  DiscreteDistribution z(std::vector<float>{0.0f, 0.0f, 0.0f, 0.0f});
  EXPECT_FLOAT_EQ(z.pmf(2), 0.25f);
  EXPECT_EQ(z.sample(0.6f), 2u);
  EXPECT_EQ(z.sample(kOneMinusEpsilon), 3u);
}

TEST(Sampling, DiscreteDistributionOfOneEntryIsCertainAndKeepsU) {
  // The inline single-bucket path (one light): index 0 with pmf 1, and u itself as the remapped number, whatever the
  // weight (zero weights are uniform, so a lone zero-weight entry is certain too).
  for (float w : {2.5f, 0.0f}) {
    DiscreteDistribution d(std::vector<float>{w});
    ASSERT_EQ(d.size(), 1u);
    for (float u : {0.0f, 0.3f, 0.999f, kOneMinusEpsilon}) {
      float pmf = -1.0f, ur = -1.0f;
      EXPECT_EQ(d.sample(u, &pmf, &ur), 0u);
      EXPECT_EQ(pmf, 1.0f);
      EXPECT_EQ(ur, u);
    }
  }
}

TEST(Sampling, DiscreteDistributionKeepsItsInvariantsForAnyWeights) {
  // Random weight tables with zero, infinite and NaN entries: the cdf runs from exactly 0 to exactly 1 without
  // decreasing, a weight that is not finite and positive gets probability 0, and any u, even outside [0, 1), picks
  // an entry of positive probability with a remapped u in [0, 1), also at each bucket's two ends.
  Pcg32 rng(11, 11);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (int trial = 0; trial < 3000; ++trial) {
    const size_t n = 2 + size_t(trial % 9);
    std::vector<float> w(n);
    for (float& x : w)
      x = rng.next_float() < 0.3f ? 0.0f : std::ldexp(rng.next_float(), int(20 * rng.next_float()) - 10);
    if (trial % 3 == 0) w[size_t(trial / 3) % n] = inf;
    if (trial % 4 == 0) w[size_t(trial / 4) % n] = nan;
    bool any_positive = false;
    for (float x : w) any_positive |= std::isfinite(x) && x > 0.0f;
    DiscreteDistribution d(w);
    ASSERT_EQ(d.cdf.front(), 0.0f);
    ASSERT_EQ(d.cdf.back(), 1.0f);
    for (size_t k = 0; k < n; ++k) {
      ASSERT_LE(d.cdf[k], d.cdf[k + 1]) << trial;
      ASSERT_TRUE(std::isfinite(d.pmf(k))) << trial;
      if (any_positive && !(std::isfinite(w[k]) && w[k] > 0.0f)) {
        ASSERT_EQ(d.pmf(k), 0.0f) << trial << " " << k;
      }
    }
    std::vector<float> us = {-0.5f, -0.0f, 0.0f, kOneMinusEpsilon, 1.0f, 2.0f};
    for (float c : d.cdf) {
      if (c < 1.0f) us.push_back(c);
      if (c > 0.0f) us.push_back(std::nextafter(c, 0.0f));
    }
    for (float u : us) {
      float pmf = -1.0f, ur = -1.0f;
      const size_t k = d.sample(u, &pmf, &ur);
      ASSERT_LT(k, n);
      ASSERT_GT(pmf, 0.0f) << "trial " << trial << " u " << u << " picked entry " << k << " of weight " << w[k];
      ASSERT_EQ(pmf, d.pmf(k));
      ASSERT_GE(ur, 0.0f) << trial << " u " << u;
      ASSERT_LT(ur, 1.0f) << trial << " u " << u;
    }
  }
}

TEST(Frame, OrthonormalEverywhereIncludingMinusZ) {
  Pcg32 rng(3, 3);
  std::vector<vec3> normals = {vec3(0, 0, -1), vec3(0, 0, 1), glm::normalize(vec3(1e-7f, 0, -1)),
                               glm::normalize(vec3(0, 1e-7f, -1)), vec3(1, 0, 0), vec3(0, -1, 0)};
  for (int i = 0; i < 10000; ++i) normals.push_back(sample_uniform_sphere(vec2(rng.next_float(), rng.next_float())));
  for (vec3 n : normals) {
    Frame f = Frame::from_normal(n);
    EXPECT_NEAR(glm::length(f.s), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.s, f.t), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.s, n), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.t, n), 0.0f, 1e-5f);
    EXPECT_GT(glm::dot(glm::cross(f.s, f.t), n), 0.999f);  // right-handed
    vec3 v(0.3f, -0.4f, 0.866f);
    vec3 back = f.to_local(f.to_world(v));
    EXPECT_NEAR(glm::length(back - v), 0.0f, 1e-5f);
  }
}

}  // namespace
}  // namespace pt
