// The generated torus knot: a closed, consistently oriented, outward-facing tube with the promised triangle
// count, shading normals that are the true surface normals, and the shape of the curve it follows.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "scene/procedural.h"

namespace pt {
namespace {

/// Every directed edge appears exactly once and its reverse exactly once: the mesh is closed (each edge shared by
/// two triangles) and the two triangles at each edge are oriented alike.
void expect_closed_and_consistent(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (uvec3 t : m.indices)
    for (int k = 0; k < 3; ++k) edges[{t[k], t[(k + 1) % 3]}]++;
  size_t bad = 0;
  for (const auto& [e, count] : edges)
    if (count != 1 || !edges.count({e.second, e.first})) ++bad;
  EXPECT_EQ(bad, 0u);
}

TEST(TorusKnot, IsClosedOutwardAndCounted) {
  for (auto [p, q, segments, sides] : {std::tuple{2, 3, 64, 12}, std::tuple{3, 2, 90, 5}, std::tuple{3, 7, 300, 3}}) {
    SCOPED_TRACE(::testing::Message() << p << "," << q << " " << segments << "x" << sides);
    TorusKnotParams k;
    k.p = p;
    k.q = q;
    k.segments = segments;
    k.sides = sides;
    k.tube = 0.08f;
    Mesh m = make_torus_knot(k, 7);
    EXPECT_EQ(m.indices.size(), size_t(2 * segments * sides));
    EXPECT_EQ(m.positions.size(), size_t(segments * sides));
    ASSERT_EQ(m.materials.size(), m.indices.size());
    for (uint32_t id : m.materials) ASSERT_EQ(id, 7u);
    expect_closed_and_consistent(m);
    EXPECT_GT(signed_volume(m), 0.0);
  }
}

/// The (p, q) torus knot's curve at t, written out independently of make_torus_knot: radius / 3 times
/// ((2 + cos qt) cos pt, (2 + cos qt) sin pt, sin qt).
dvec3 knot_curve_point(const TorusKnotParams& k, double t) {
  const double s = double(k.radius) / 3.0, r = s * (2.0 + std::cos(k.q * t));
  return dvec3(r * std::cos(k.p * t), r * std::sin(k.p * t), s * std::sin(k.q * t));
}

TEST(TorusKnot, VolumeIsThatOfATubeAlongTheCurve) {
  // Pappus: a tube of radius r around a curve of length L encloses pi r^2 L (when it does not overlap itself).
  const TorusKnotParams k{.p = 2, .q = 3, .segments = 2000, .sides = 48, .radius = 1.0f, .tube = 0.05f};
  Mesh m = make_torus_knot(k);
  double length = 0.0;
  const int n = 20000;
  auto curve = [&](double t) { return knot_curve_point(k, t); };
  for (int i = 0; i < n; ++i) length += glm::length(curve(2 * kPi * (i + 1) / n) - curve(2 * kPi * i / n));
  double expected = kPi * 0.05 * 0.05 * length;
  EXPECT_NEAR(signed_volume(m) / expected, 1.0, 0.01);
}

TEST(TorusKnot, ShadingNormalsAreUnitOutwardAndPerpendicularToTheSurface) {
  TorusKnotParams k;
  k.segments = 400;
  k.sides = 16;
  Mesh m = make_torus_knot(k);
  ASSERT_EQ(m.normal_indices.size(), m.indices.size());
  size_t facing_in = 0;
  for (size_t t = 0; t < m.indices.size(); ++t) {
    uvec3 i = m.indices[t], ni = m.normal_indices[t];
    vec3 a = m.positions[i.x], b = m.positions[i.y], c = m.positions[i.z];
    vec3 ng = glm::normalize(glm::cross(b - a, c - a));
    for (int c3 = 0; c3 < 3; ++c3) {
      vec3 n = m.normals[ni[c3]];
      EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
      if (glm::dot(n, ng) <= 0.0f) ++facing_in;
    }
  }
  // Vertices are stored ring by ring. Along the curve the surface moves perpendicular to its normal: the edge to
  // the same angle on the next ring is (nearly) perpendicular to the normal at either end.
  double worst_tangential = 0.0;
  for (int r = 0; r < k.segments; ++r)
    for (int j = 0; j < k.sides; ++j) {
      size_t here = size_t(r * k.sides + j), next = size_t(((r + 1) % k.segments) * k.sides + j);
      vec3 along = glm::normalize(m.positions[next] - m.positions[here]);
      worst_tangential = std::max(worst_tangential, double(std::abs(glm::dot(along, m.normals[here]))));
    }
  EXPECT_EQ(facing_in, 0u);
  EXPECT_LT(worst_tangential, 0.05);
}

TEST(TorusKnot, FollowsTheCurve) {
  // Every vertex is at distance `tube` from the curve point of its ring, and the rings' centers span the knot's
  // extent: radius (2 + 1) / 3 in x and y, radius / 3 in z.
  const TorusKnotParams k{.p = 2, .q = 3, .segments = 120, .sides = 10, .radius = 2.0f, .tube = 0.1f};
  Mesh m = make_torus_knot(k);
  AABB centers;
  for (int i = 0; i < k.segments; ++i) {
    dvec3 c(0.0);
    for (int j = 0; j < k.sides; ++j) c += dvec3(m.positions[size_t(i * k.sides + j)]);
    c /= double(k.sides);
    for (int j = 0; j < k.sides; ++j)
      EXPECT_NEAR(glm::length(dvec3(m.positions[size_t(i * k.sides + j)]) - c), 0.1, 1e-4);
    centers.extend(vec3(c));
  }
  EXPECT_NEAR(centers.hi.x, 2.0f, 0.01f);
  EXPECT_NEAR(centers.hi.z, 2.0f / 3.0f, 0.01f);
  EXPECT_NEAR(centers.lo.z, -2.0f / 3.0f, 0.01f);
}

TEST(TorusKnot, RingsSitAtEvenStepsOfTheWholeCurve) {
  // Ring i is centred on the (p, q) torus knot's point at t = 2 pi i / segments (knot_curve_point): a ring at the
  // wrong parameter still lies on the curve (the test above), but the rings would bunch up and the last quad
  // would bridge the gap back to the first.
  const TorusKnotParams k{.p = 3, .q = 5, .segments = 50, .sides = 8, .radius = 2.0f, .tube = 0.1f};
  const Mesh m = make_torus_knot(k);
  for (int i = 0; i < k.segments; ++i) {
    dvec3 c(0.0);  // the ring's centre: the mean of its evenly spaced vertices
    for (int j = 0; j < k.sides; ++j) c += dvec3(m.positions[size_t(i * k.sides + j)]);
    c /= double(k.sides);
    const dvec3 expected = knot_curve_point(k, 2.0 * std::numbers::pi * i / k.segments);
    EXPECT_LT(glm::length(c - expected), 1e-5) << "ring " << i;
  }
}

TEST(SignedVolume, OfAUnitCubeIsOneAndFlipsWithTheWinding) {
  Mesh cube;
  for (int i = 0; i < 8; ++i) cube.positions.push_back(vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  // Faces counter-clockwise seen from outside.
  uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& q : quads) {
    cube.indices.push_back({q[0], q[1], q[2]});
    cube.indices.push_back({q[0], q[2], q[3]});
  }
  EXPECT_NEAR(signed_volume(cube), 1.0, 1e-12);
  for (uvec3& t : cube.indices) std::swap(t.y, t.z);
  EXPECT_NEAR(signed_volume(cube), -1.0, 1e-12);
}

}  // namespace
}  // namespace pt
