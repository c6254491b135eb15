// Which emissive triangles merge into one parallelogram light (src/render/emissive_pairs.cpp):
//  - a quad's two triangles pair wherever they stand in the mesh, and the pair's light is the quad;
//  - a shuffled grid of quads, each split along either diagonal from any corner, pairs back into exactly its quads
//    (adjacent quads' triangles also form sheared parallelograms: rectangles must win);
//  - sheared parallelograms pair apart too; only candidates of one material pair; an edge shared by more than four
//    candidates pairs nothing; -0 and +0 are one corner;
//  - neighbours in the mesh pair in its order, as they did before pairs apart were looked for.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "core/rng.h"
#include "render/emissive_pairs.h"
#include "render/render_scene.h"
#include "render/scene_builders.h"

namespace pt {
namespace {

struct Soup {
  std::vector<vec3> corners;
  std::vector<uint32_t> material;
  std::vector<uint8_t> candidate;
  void add(vec3 a, vec3 b, vec3 c, uint32_t m = 0, bool cand = true) {
    corners.insert(corners.end(), {a, b, c});
    material.push_back(m);
    candidate.push_back(cand ? 1 : 0);
  }
  std::vector<int32_t> pairs() const { return pair_parallelograms(corners, material, candidate); }
};

TEST(EmissivePairs, AQuadsTrianglesPairWhereverTheyStandInTheMesh) {
  // The quad (0,0,0)-(2,0,0)-(2,0,1)-(0,0,1) split along either diagonal, its halves apart in the mesh and in either
  // order, with unrelated triangles around them.
  const vec3 q[4] = {vec3(0, 0, 0), vec3(2, 0, 0), vec3(2, 0, 1), vec3(0, 0, 1)};
  const vec3 far[3] = {vec3(10, 5, 0), vec3(11, 5, 0), vec3(10, 5, 1)};
  for (int diagonal = 0; diagonal < 2; ++diagonal)
    for (int gap = 1; gap <= 3; ++gap)
      for (bool reversed : {false, true}) {
        SCOPED_TRACE(testing::Message() << "diagonal " << diagonal << " gap " << gap << " reversed " << reversed);
        const int a = diagonal, b = diagonal + 1, c = diagonal + 2, d = (diagonal + 3) % 4;
        Soup s;
        s.add(far[0], far[1], far[2]);
        if (reversed)
          s.add(q[c], q[d], q[a]);
        else
          s.add(q[a], q[b], q[c]);
        for (int k = 0; k < gap; ++k) s.add(far[0] + vec3(0, k + 1, 0), far[1] + vec3(0, k + 1, 0), far[2]);
        if (reversed)
          s.add(q[a], q[b], q[c]);
        else
          s.add(q[c], q[d], q[a]);
        const std::vector<int32_t> p = s.pairs();
        const int first = 1, second = 2 + gap;
        EXPECT_EQ(p[first], second);
        EXPECT_EQ(p[second], first);
        for (size_t t = 0; t < p.size(); ++t)
          if (int(t) != first && int(t) != second) {
            EXPECT_EQ(p[t], -1) << t;
          }
        vec3 corner, e1, e2;
        ASSERT_TRUE(parallelogram_of(&s.corners[3 * first], &s.corners[3 * second], corner, e1, e2));
        EXPECT_FLOAT_EQ(glm::length(glm::cross(e1, e2)), 2.0f);
      }
}

TEST(EmissivePairs, AShuffledGridOfQuadsPairsBackIntoItsQuads) {
  // A 5 x 4 grid of unit quads in the plane y = 1, each split along a random diagonal starting at a random corner,
  // its 40 triangles shuffled. Triangles of neighbouring quads across a shared edge form sheared parallelograms
  // too; every triangle must pair with the other half of its own quad.
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    Pcg32 rng(seed, 7);
    struct Tri {
      vec3 v[3];
      int quad;
    };
    std::vector<Tri> tris;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 4; ++j) {
        const vec3 q[4] = {vec3(i, 1, j), vec3(i, 1, j + 1), vec3(i + 1, 1, j + 1), vec3(i + 1, 1, j)};
        const int start = int(rng.next_u32() % 4);  // the diagonal: 0-2 for an even start, 1-3 for an odd one
        auto at = [&](int k) { return q[(start + k) % 4]; };
        const int turn[2] = {int(rng.next_u32() % 3), int(rng.next_u32() % 3)};  // each triangle's first corner
        const vec3 halves[2][3] = {{at(0), at(1), at(2)}, {at(2), at(3), at(0)}};
        for (int h = 0; h < 2; ++h)
          tris.push_back({{halves[h][turn[h]], halves[h][(turn[h] + 1) % 3], halves[h][(turn[h] + 2) % 3]}, 4 * i + j});
      }
    for (size_t k = tris.size() - 1; k > 0; --k) std::swap(tris[k], tris[rng.next_u32() % (k + 1)]);
    Soup s;
    for (const Tri& t : tris) s.add(t.v[0], t.v[1], t.v[2]);
    const std::vector<int32_t> p = s.pairs();
    for (size_t t = 0; t < tris.size(); ++t) {
      ASSERT_GE(p[t], 0) << "seed " << seed << " triangle " << t;
      EXPECT_EQ(p[p[t]], int32_t(t)) << "seed " << seed;
      EXPECT_NE(p[t], int32_t(t)) << "seed " << seed;
      EXPECT_EQ(tris[p[t]].quad, tris[t].quad) << "seed " << seed << " triangle " << t;
    }
  }
}

TEST(EmissivePairs, ShearedParallelogramsPairApartToo) {
  // A strip of four triangles, every two neighbours in it a sheared parallelogram: T0 (a, b, c), T1 (b, d, c),
  // T2 (c, d, e), T3 (d, f, e), written T0, T2, T3, T1. T2-T3 are neighbours in the mesh and pair first; T0 pairs
  // with T1 three places on (T1 could also pair with T2, taken).
  const vec3 a(0, 0, 0), b(1, 0, 0), c(0.5f, 0, 1), d(1.5f, 0, 1), e(1, 0, 2), f(2, 0, 2);
  Soup s;
  s.add(a, b, c);
  s.add(c, d, e);
  s.add(d, f, e);
  s.add(b, d, c);
  EXPECT_EQ(s.pairs(), (std::vector<int32_t>{3, 2, 1, 0}));
}

TEST(EmissivePairs, OnlyCandidatesOfOneMaterialPair) {
  // Case 0 pairs; in case 1 the first triangle, in case 2 the second is no candidate; in case 3 they differ in
  // material. Each apart in the mesh and as neighbours.
  const vec3 q[4] = {vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 0, 1), vec3(0, 0, 1)};
  for (bool apart : {true, false})
    for (int kase = 0; kase < 4; ++kase) {
      Soup s;
      s.add(q[0], q[1], q[2], 0, kase != 1);
      if (apart) s.add(vec3(5), vec3(6, 5, 5), vec3(5, 5, 6));
      s.add(q[2], q[3], q[0], kase == 3 ? 1u : 0u, kase != 2);
      const std::vector<int32_t> p = s.pairs();
      const int last = apart ? 2 : 1;
      if (kase == 0) {
        EXPECT_EQ(p[0], last) << "apart " << apart;
        EXPECT_EQ(p[last], 0) << "apart " << apart;
      } else {
        EXPECT_EQ(p, std::vector<int32_t>(last + 1, -1)) << "case " << kase << " apart " << apart;
      }
    }
}

TEST(EmissivePairs, CoordinatesOfZeroOfEitherSignAreTheSameCorner) {
  // parallelogram_of compares corners with ==, so -0 and +0 are one corner; the edge lookup must agree.
  Soup s;
  s.add(vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 0, 1));
  s.add(vec3(5), vec3(6, 5, 5), vec3(5, 5, 6));
  s.add(vec3(1, 0, 1), vec3(0, 0, 1), vec3(-0.0f, -0.0f, -0.0f));
  const std::vector<int32_t> p = s.pairs();
  EXPECT_EQ(p[0], 2);
  EXPECT_EQ(p[2], 0);
}

TEST(EmissivePairs, AnEdgeSharedByMoreThanFourTrianglesPairsNothing) {
  // A parallelogram's two halves on an edge that three more triangles share (a non-manifold fan): left alone, as
  // documented. With two more (four on the edge) the pair is made.
  for (int extra : {2, 3}) {
    Soup s;
    s.add(vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 0, 1));
    for (int k = 0; k < extra; ++k) s.add(vec3(0, 0, 0), vec3(1, 0, 1), vec3(0.5f, float(k + 1), 0.5f));
    s.add(vec3(1, 0, 1), vec3(0, 0, 1), vec3(0, 0, 0));
    const std::vector<int32_t> p = s.pairs();
    EXPECT_EQ(p.back(), extra == 2 ? 0 : -1) << extra << " more on the edge";
  }
}

TEST(EmissivePairs, TrianglesWithARepeatedCornerPairWithNothing) {
  // (p, p, q) then (p, r, s): p of the second matched both corners of the first, and the second's unshared corner
  // was read at index 3, past the end of the array when it is the last triangle (AddressSanitizer's build, in CI,
  // reports that read; the pairs are checked in every build). Exactly sized arrays, so the read is past the heap
  // block.
  const vec3 p(0, 0, 0), q(1, 0, 0), r(0, 0, 1), w(1, 0, 1);
  const std::vector<vec3> corners = {p, p, q, p, r, w};
  const std::vector<uint32_t> material = {0, 0};
  const std::vector<uint8_t> candidate = {1, 1};
  EXPECT_EQ(pair_parallelograms(corners, material, candidate), (std::vector<int32_t>{-1, -1}));
  vec3 c, e1, e2;
  EXPECT_FALSE(parallelogram_of(&corners[0], &corners[3], c, e1, e2));
  EXPECT_FALSE(parallelogram_of(&corners[3], &corners[0], c, e1, e2));
  // Apart in the mesh, through the edge search: (q, p, p) first, an unrelated triangle, then (p, q, w).
  const std::vector<vec3> apart = {q, p, p, vec3(5), vec3(6, 5, 5), vec3(5, 5, 6), p, q, w};
  EXPECT_EQ(pair_parallelograms(apart, std::vector<uint32_t>{0, 0, 0}, std::vector<uint8_t>{1, 1, 1}),
            (std::vector<int32_t>{-1, -1, -1}));
}

TEST(EmissivePairs, NeighboursInTheMeshPairInItsOrder) {
  // Three triangles where 0-1 and 1-2 both form sheared parallelograms (a strip): 0-1 pair, as the lights were
  // made before pairs apart were looked for, and 2 is left alone.
  const vec3 a(0, 0, 0), b(1, 0, 0), c(0.5f, 0, 1), d(1.5f, 0, 1);
  const vec3 e(1, 0, 2);
  Soup s;
  s.add(a, b, c);
  s.add(b, d, c);
  s.add(c, d, e);
  const std::vector<int32_t> p = s.pairs();
  EXPECT_EQ(p, (std::vector<int32_t>{1, 0, -1}));
  // The same three written (c, d, e), (a, b, c), (b, d, c): the neighbours 1-2 pair before the pair 0-2 apart.
  Soup apart;
  apart.add(c, d, e);
  apart.add(a, b, c);
  apart.add(b, d, c);
  EXPECT_EQ(apart.pairs(), (std::vector<int32_t>{-1, 2, 1}));
  // A rectangle goes before a sheared pair earlier in the mesh: (g, k, h) forms a sheared parallelogram with its
  // neighbour (h, k, m), and (h, k, m) a rectangle with its other neighbour (m, n, h).
  const vec3 h(0, 0, 0), k(1, 0, 0), m(1, 0, 1), n(0, 0, 1), g(0, 0, -1);
  Soup rect;
  rect.add(g, k, h);
  rect.add(h, k, m);
  rect.add(m, n, h);
  vec3 corner, e1, e2;
  ASSERT_TRUE(parallelogram_of(&rect.corners[0], &rect.corners[3], corner, e1, e2));
  ASSERT_FALSE(at_right_angle(e1, e2));
  EXPECT_EQ(rect.pairs(), (std::vector<int32_t>{-1, 2, 1}));
}

TEST(EmissivePairs, ALightPerQuadOfAShuffledEmissiveGrid) {
  // Through the render scene: a 3 x 2 grid of emissive quads, triangles reversed in order, gives six rectangle
  // lights of area 1 (the whole surface), each triangle mapped to its quad's light.
  Scene s;
  test::add_material(s, test::diffuse(vec3(0.5f)));
  const uint32_t lamp = test::add_material(s, test::diffuse(vec3(0.0f), vec3(2.0f)));
  Mesh m;
  for (int i = 0; i <= 3; ++i)
    for (int j = 0; j <= 2; ++j) m.positions.push_back(vec3(i, 1, j));
  auto id = [](int i, int j) { return uint32_t(3 * i + j); };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j) {
      m.indices.push_back(uvec3(id(i, j), id(i, j + 1), id(i + 1, j + 1)));
      m.indices.push_back(uvec3(id(i + 1, j + 1), id(i + 1, j), id(i, j)));
    }
  std::reverse(m.indices.begin(), m.indices.end());
  std::rotate(m.indices.begin(), m.indices.begin() + 1, m.indices.end());  // no quad's halves are consecutive
  m.materials.assign(m.indices.size(), lamp);
  s.meshes.push_back(m);
  RenderScene rs = make_render_scene(s);
  ASSERT_EQ(rs.lights.lights.size(), 6u);
  for (const Light& l : rs.lights.lights) {
    EXPECT_EQ(l.kind, LightKind::rect);
    EXPECT_TRUE(l.rectangular);
    EXPECT_NEAR(l.area, 1.0f, 1e-6f);
  }
  for (size_t t = 0; t < m.indices.size(); ++t) {
    const int32_t light = rs.tri_light[t];
    ASSERT_GE(light, 0);
    const Light& l = rs.lights.lights[light];
    const vec3 centre = l.p0 + 0.5f * (l.e1 + l.e2);
    for (int k = 0; k < 3; ++k) {
      const vec3 v = rs.geo->tri_vertices[3 * t + k];
      EXPECT_LE(glm::length(v - centre), 0.7072f) << "triangle " << t << " is not on its light's quad";
    }
  }
}

}  // namespace
}  // namespace pt
