// The 8-wide BVH (src/accel/bvh8*.cpp) against references:
//  - the SIMD node test equals the scalar one bit for bit, and each slot equals the binary tree's intersect_box;
//  - the 4-lane triangle test equals intersect_triangle lane by lane, bit for bit, padding lanes never hit;
//  - closest and any hits on a closed 40k-triangle mesh equal a brute-force loop;
//  - the parallel build is deterministic, and the binned SAH is within 5% of the full-sweep SAH build;
//  - the collapse into wide nodes reaches the SAH-optimal cover of a memoized reference recursion.
// (test_bvh.cpp covers the edge-case soups through make_trace_geometry, which uses this tree.)
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>

#include "accel/geometry.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "scene/procedural.h"

namespace pt {
namespace {

vec3 rand3(Pcg32& rng) { return vec3(rng.next_float(), rng.next_float(), rng.next_float()); }

/// Random directions, a fifth with one or two exact zero components (0 * inf in the slab test).
vec3 awkward_direction(Pcg32& rng, int i) {
  vec3 d = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
  if (i % 5 == 1) d[i % 3] = 0.0f;
  if (i % 5 == 2) d[i % 3] = 0.0f, d[(i + 1) % 3] = 0.0f;
  if (d == vec3(0.0f)) d.z = 1.0f;
  return glm::normalize(d);
}

TEST(Bvh8, SimdNodeTestEqualsScalarAndNeverMissesWhatTheSlabTestHits) {
  Pcg32 rng(7, 1);
  int hits = 0, lanes = 0, extra = 0;
  for (int i = 0; i < 200000; ++i) {
    Bvh8Node node;
    AABB boxes[8];
    for (int s = 0; s < 8; ++s) {
      vec3 a = rand3(rng) * 4.0f - 2.0f, b = a + rand3(rng) * (s == 3 ? 0.0f : 1.5f);  // slot 3: a point
      if (s == 5) b.y = a.y;                                                          // slot 5: flat
      boxes[s] = {a, b};
      if (s == 7 && i % 2) boxes[s] = AABB{};  // an empty slot, as make_bvh8 writes it
      set_slot(node, s, boxes[s]);
      node.child[s] = uint32_t(s);
    }
    Ray ray{rand3(rng) * 6.0f - 3.0f, awkward_direction(rng, i), kInfinity};
    if (i % 5 > 2) {  // aimed at a point of one of the boxes
      const AABB& aim = boxes[rng.next_u32() % 7];
      ray.dir = glm::normalize(aim.lo + rand3(rng) * aim.extent() - ray.org);
    }
    if (i % 7 == 3) ray.org[i % 3] = boxes[i % 8].lo[i % 3];  // origin on a slab plane
    if (i % 3 == 1) ray.tmax = rng.next_float() * 4.0f;
    const NodeRay nr = make_node_ray(ray);
    alignas(32) float t_simd[8], t_scalar[8];
    const uint32_t m_simd = intersect_node8(node, nr, ray.tmax, t_simd);
    const uint32_t m_scalar = intersect_node8_scalar(node, nr, ray.tmax, t_scalar);
    ASSERT_EQ(m_simd, m_scalar) << "ray " << i;
    ASSERT_EQ(std::memcmp(t_simd, t_scalar, sizeof t_simd), 0) << "ray " << i;
    // Against the binary tree's slab test: never a miss where it hits, the same entry distance within rounding;
    // extra hits only within rounding (or, with FMA, on axes the ray is exactly parallel to: those never cull).
    const RayBoxData rd = make_ray_box_data(ray);
    const bool parallel = ray.dir.x == 0.0f || ray.dir.y == 0.0f || ray.dir.z == 0.0f;
    for (int s = 0; s < 8; ++s) {
      if (boxes[s].empty()) {
        ASSERT_FALSE(m_simd >> s & 1);
        continue;
      }
      const float t = intersect_box(boxes[s], rd, ray.tmax);
      const bool hit = m_simd >> s & 1;
      if (t != kInfinity) {
        ASSERT_TRUE(hit) << "ray " << i << " slot " << s << " missed";
        ASSERT_LE(t_simd[s], t * (1.0f + 1e-6f)) << "ray " << i << " slot " << s;
        if (!parallel) {  // lower by at most the widening of org * inv (see NodeRay)
          float widening = 0.0f;
          for (int a = 0; a < 3; ++a) widening = std::max(widening, std::abs(ray.org[a] * nr.inv_dir[a]) * 0x1p-20f);
          ASSERT_GE(t_simd[s], t * (1.0f - 1e-6f) - widening - 1e-30f) << "ray " << i << " slot " << s;
        }
      } else if (hit && !parallel) {
        ++extra;
      }
      hits += t != kInfinity;
      lanes++;
    }
  }
  EXPECT_GT(hits, lanes / 40);  // about 5%: mostly the boxes rays were aimed at
  EXPECT_LT(hits, lanes * 9 / 10);
  // The widening lets through degenerate boxes (points, flat) a ray passes within rounding of: rare, and only costs.
  EXPECT_LE(extra, lanes / 200) << "boxes hit only by the node test";
  RecordProperty("simd", bvh8_simd_name());
}

/// Triangles of every kind a lane-wise test can get wrong: random, degenerate (repeated vertex, collinear), tiny,
/// huge, and pairs sharing an edge that rays are aimed at exactly.
void fill_awkward_block(Pcg32& rng, int i, Tri4& blk, vec3 (&tri)[4][3], int& valid) {
  valid = 1 + int(rng.next_u32() % 4);
  for (int lane = 0; lane < 4; ++lane) {
    vec3 c = rand3(rng) * 2.0f - 1.0f;
    float size = (i + lane) % 9 == 0 ? 1e-4f : ((i + lane) % 9 == 1 ? 1e3f : 1.0f);
    for (int k = 0; k < 3; ++k) tri[lane][k] = c + size * (rand3(rng) - 0.5f);
    if ((i + lane) % 11 == 0) tri[lane][2] = tri[lane][0];                                      // repeated vertex
    if ((i + lane) % 13 == 0) tri[lane][2] = 0.25f * tri[lane][0] + 0.75f * tri[lane][1];    // collinear
    if (lane == 1 && i % 4 == 0) tri[1][0] = tri[0][1], tri[1][1] = tri[0][0];               // shares an edge
  }
  for (int lane = 0; lane < 4; ++lane) {
    const int src = lane < valid ? lane : 0;
    blk.prim[lane] = lane < valid ? uint32_t(100 + lane) : kInvalidPrim;
    set_lane(blk, lane, tri[src][0], tri[src][1], tri[src][2]);
  }
}

TEST(Bvh8, FourLaneTriangleTestEqualsScalarTestBitForBit) {
  Pcg32 rng(9, 2);
  int hits = 0, edge_rays = 0;
  for (int i = 0; i < 300000; ++i) {
    Tri4 blk;
    vec3 tri[4][3];
    int valid = 0;
    fill_awkward_block(rng, i, blk, tri, valid);
    // Aim at a vertex, an edge point or the interior of one of the triangles, or anywhere.
    const int lane = int(rng.next_u32() % 4);
    vec3 target = rand3(rng) * 2.0f - 1.0f;
    switch (i % 4) {
      case 0: target = tri[lane][i % 3]; break;
      case 1: target = 0.5f * (tri[lane][0] + tri[lane][1]); ++edge_rays; break;
      case 2: target = (tri[lane][0] + tri[lane][1] + tri[lane][2]) / 3.0f; break;
      default: break;
    }
    Ray ray{target - 3.0f * awkward_direction(rng, i), vec3(0.0f), kInfinity};
    ray.dir = glm::normalize(target - ray.org);
    if (i % 3 == 1) ray.tmax = rng.next_float() * 6.0f;
    const WatertightRay w = make_watertight_ray(ray);
    // The reference: the scalar test lane by lane, shrinking tmax as a scalar loop would.
    int want_lane = -1;
    TriangleHit want{};
    float tmax = ray.tmax;
    for (int l = 0; l < valid; ++l) {
      TriangleHit th;
      if (intersect_triangle(w, tmax, tri[l][0], tri[l][1], tri[l][2], th)) want = th, want_lane = l, tmax = th.t;
    }
    const Tri4Hit got = intersect_tri4(blk, w, ray.tmax);
    ASSERT_EQ(got.lane, want_lane) << "ray " << i;
    ASSERT_EQ(occluded_tri4(blk, w, ray.tmax), want_lane >= 0) << "ray " << i;
    if (want_lane < 0) continue;
    ++hits;
    ASSERT_EQ(got.t, want.t) << "ray " << i;
    ASSERT_EQ(got.b1, want.b1) << "ray " << i;
    ASSERT_EQ(got.b2, want.b2) << "ray " << i;
  }
  EXPECT_GT(hits, 60000);
  EXPECT_GT(edge_rays, 50000);
}

// A hit whose distance underflows in float: the triangle lies a denormal step beyond the ray's origin, so the
// distance's numerator t_scaled is a few denormal steps, rounded per term, and divided by a determinant above 2 it
// rounds to zero. The double-precision decision (small_t_is_positive) finds the hit in front of the origin; the
// distance reported must then be the smallest positive float, as intersect_triangle reports it, never 0 (a hit at
// 0 is "behind or at the origin" to every caller that compares distances).
TEST(Bvh8, AHitWhoseDistanceUnderflowsIsStillInFront) {
  const Ray ray{vec3(0.0f), vec3(0, 0, 1), kInfinity};
  const WatertightRay w = make_watertight_ray(ray);
  const float z = std::numeric_limits<float>::denorm_min();
  int smallest = 0;
  for (int k = 0; k < 400; ++k) {
    // The origin at barycentrics (1.4, 0.4, 0.4) / 2.2 of a right triangle in the plane z = denorm_min, scaled
    // so that twice its area (the determinant) sweeps about 1 to 3.5.
    const float b = 0.8f + 0.0025f * float(k);
    const vec3 v1(b, 0.0f, z), v2(0.0f, b, z), v0(-0.4f / 1.4f * b, -0.4f / 1.4f * b, z);
    TriangleHit want;
    ASSERT_TRUE(intersect_triangle(w, ray.tmax, v0, v1, v2, want)) << "b " << b;
    ASSERT_GT(want.t, 0.0f) << "b " << b;
    Tri4 blk;
    for (int lane = 0; lane < 4; ++lane) {
      blk.prim[lane] = lane == 0 ? 7u : kInvalidPrim;
      set_lane(blk, lane, v0, v1, v2);
    }
    const Tri4Hit got = intersect_tri4(blk, w, ray.tmax);
    ASSERT_EQ(got.lane, 0) << "b " << b;
    EXPECT_EQ(got.t, want.t) << "b " << b;
    smallest += want.t == z;
  }
  // Most of the family reports the smallest float; the distances that rounded to zero on the way are among them
  // (the mutation that drops the clamp, TV8, fails this test).
  EXPECT_GT(smallest, 100) << "the family must reach the smallest distances";
}

/// The closed torus knot: every edge shared by two triangles.
std::vector<vec3> knot_triangles(int segments, int sides, vec3 offset = vec3(0.0f)) {
  TorusKnotParams p;
  p.segments = segments;
  p.sides = sides;
  Mesh m = make_torus_knot(p);
  std::vector<vec3> tv;
  for (const uvec3& t : m.indices)
    for (int k = 0; k < 3; ++k) tv.push_back(m.positions[t[k]] + offset);
  return tv;
}

TEST(Bvh8, ClosestAndAnyHitOnAClosedMeshEqualBruteForce) {
  for (vec3 offset : {vec3(0.0f), vec3(1e4f, -3e4f, 2e4f)}) {
    const std::vector<vec3> tv = knot_triangles(300, 64, offset);  // 38,400 triangles
    const TraceGeometry g = make_trace_geometry(tv, {});
    const AABB b = g.bounds();
    Pcg32 rng(3, 4);
    int hits = 0, ties = 0;
    for (int i = 0; i < 3000; ++i) {
      // From outside toward a random point of the box, from a vertex along the surface, or from inside the tube.
      vec3 target = b.lo + rand3(rng) * b.extent();
      vec3 org = b.center() + 2.0f * glm::length(b.extent()) * sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
      if (i % 3 == 1) target = tv[rng.next_u32() % tv.size()];
      if (i % 3 == 2) {
        const size_t t = rng.next_u32() % (tv.size() / 3);
        org = (tv[3 * t] + tv[3 * t + 1] + tv[3 * t + 2]) / 3.0f;
        target = org + awkward_direction(rng, i);
      }
      Ray ray{org, glm::normalize(target - org), kInfinity};
      if (i % 5 == 4) ray.tmax = rng.next_float() * glm::length(b.extent());
      const WatertightRay w = make_watertight_ray(ray);
      Hit want;
      want.t = ray.tmax;
      bool want_hit = false;
      for (uint32_t t = 0; t < tv.size() / 3; ++t) {
        TriangleHit th;
        if (intersect_triangle(w, want.t, tv[3 * t], tv[3 * t + 1], tv[3 * t + 2], th))
          want = {th.t, t, th.b1, th.b2}, want_hit = true;
      }
      Ray r = ray;
      Hit got;
      const bool got_hit = intersect_closest(g, r, got);
      ASSERT_EQ(got_hit, want_hit) << "ray " << i;
      ASSERT_EQ(intersect_any(g, ray), want_hit) << "ray " << i;
      if (!want_hit) continue;
      ++hits;
      ASSERT_EQ(r.tmax, got.t);
      // The hit names where the traversal read its triangle; shading reads the vertices there (make_surface_hit).
      ASSERT_NE(got.vertices, nullptr);
      for (int k = 0; k < 3; ++k) ASSERT_EQ(lane_vertex(got.vertices, k), tv[3 * got.prim + k]) << "ray " << i;
      if (got.prim != want.prim) {
        // Rays aimed at a shared vertex or edge hit several triangles within rounding of each other; the one that
        // counts as closest can depend on the order they are tested in. The hit found must be real and as close.
        TriangleHit th;
        ASSERT_TRUE(intersect_triangle(w, ray.tmax, tv[3 * got.prim], tv[3 * got.prim + 1], tv[3 * got.prim + 2], th));
        ASSERT_EQ(th.t, got.t);
        ASSERT_LE(std::abs(got.t - want.t), 1e-6f * want.t) << "ray " << i;
        ++ties;
      } else {
        ASSERT_EQ(got.t, want.t) << "ray " << i;
        ASSERT_EQ(got.b1, want.b1);
        ASSERT_EQ(got.b2, want.b2);
      }
    }
    EXPECT_GT(hits, 1500);
    EXPECT_LT(ties, 100);
  }
}

// After a refit the leaf blocks hold the moved vertices, and a hit's vertices are those of its triangle, bit for
// bit, in every lane (rays through each triangle's centroid hit that triangle, whatever lane it sits in).
TEST(Bvh8, HitVerticesAreTheTrianglesOwnAfterARefit) {
  std::vector<vec3> tv = knot_triangles(60, 16);
  TraceGeometry g = make_trace_geometry(tv, {});
  for (vec3& v : tv) v = 1.5f * v + vec3(0.25f, -2.0f, 1.0f);
  refit_trace_geometry(g, tv, {});
  int checked = 0;
  for (uint32_t t = 0; t < tv.size() / 3; ++t) {
    const vec3 c = (tv[3 * t] + tv[3 * t + 1] + tv[3 * t + 2]) / 3.0f;
    const vec3 n = glm::cross(tv[3 * t + 1] - tv[3 * t], tv[3 * t + 2] - tv[3 * t]);
    if (!(glm::length(n) > 0.0f)) continue;
    Ray ray{c + 1e-3f * glm::normalize(n), -glm::normalize(n), kInfinity};
    Hit hit;
    if (!intersect_closest(g, ray, hit) || hit.prim != t) continue;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(lane_vertex(hit.vertices, k), tv[3 * t + k]) << "triangle " << t;
    ++checked;
  }
  EXPECT_GT(checked, int(tv.size() / 3) * 9 / 10);
}

TEST(Bvh8, ParallelBuildIsDeterministic) {
  const std::vector<vec3> tv = knot_triangles(800, 64);  // 102,400 triangles: several build threads
  BvhBuildOptions one, many;
  one.threads = 1;
  many.threads = 4;
  const TraceGeometry a = make_trace_geometry(tv, {}, one), b = make_trace_geometry(tv, {}, many);
  ASSERT_EQ(a.triangles.units.size(), b.triangles.units.size());
  EXPECT_EQ(std::memcmp(a.triangles.units.data(), b.triangles.units.data(), a.triangles.bytes()), 0);
  EXPECT_EQ(a.stats.sah_cost, b.stats.sah_cost);
}

TEST(Bvh8, TheSweepMakesALeafWhereNoSplitPaysAndSplitsAboveTheLimit) {
  // n copies of one box: each side of any split has the parent's area, so a split costs a node visit more than the
  // leaf and the SAH keeps the leaf, up to max_leaf_size (8 by default), above which it must split.
  const AABB unit{vec3(0.0f), vec3(1.0f)};
  for (uint32_t n : {2u, 5u, 8u, 16u}) {
    const std::vector<AABB> boxes(n, unit);
    const std::vector<vec3> centers(n, unit.center());
    const Bvh bvh = build_bvh_sweep(boxes, centers, BvhBuildOptions{});
    if (n <= 8) {
      ASSERT_EQ(bvh.nodes.size(), 1u) << n;
      EXPECT_EQ(bvh.nodes[0].count, n);
    } else {
      uint32_t in_leaves = 0;
      for (const BvhNode& node : bvh.nodes) {
        if (node.count == 0) continue;
        EXPECT_LE(node.count, 8u);
        in_leaves += node.count;
      }
      EXPECT_EQ(in_leaves, n);
      EXPECT_GT(bvh.nodes.size(), 1u);
    }
  }
}

TEST(Bvh8, BinnedSahIsWithinFivePercentOfFullSweep) {
  const std::vector<vec3> tv = knot_triangles(400, 48);
  std::vector<AABB> boxes(tv.size() / 3);
  std::vector<vec3> centers(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    for (int k = 0; k < 3; ++k) boxes[i].extend(tv[3 * i + k]);
    centers[i] = boxes[i].center();
  }
  for (int block : {1, 4}) {
    BvhBuildOptions o;
    o.leaf_block_size = block;
    const float binned = sah_cost(build_bvh(boxes, o));
    const float sweep = sah_cost(build_bvh_sweep(boxes, centers, o));
    EXPECT_LE(binned, 1.05f * sweep) << "leaf block " << block;
    EXPECT_GE(binned, 0.95f * sweep) << "leaf block " << block;
  }
}

/// The SAH cost of covering binary subtree i by at most k slot roots, straight from the definition of the
/// collapse (bvh8.cpp, CollapsePlan; Ylitie et al. 2017): a slot root is a leaf of at most 16 triangles (a block per
/// 4, each costing its box's area) or a wide node (its area plus its children's cover by 8 slots). Memoized
/// recursion in double, independent of the build's bottom-up sweep and its SIMD min-plus convolution.
struct ReferenceCollapse {
  const Bvh& bin;
  std::vector<std::array<double, 9>> memo;
  std::vector<uint32_t> count;
  explicit ReferenceCollapse(const Bvh& b) : bin(b), memo(b.nodes.size()), count(b.nodes.size(), 0) {
    for (auto& m : memo) m.fill(-1.0);
    for (size_t i = b.nodes.size(); i-- > 0;)
      count[i] = b.nodes[i].is_leaf() ? b.nodes[i].count : count[b.nodes[i].first] + count[b.nodes[i].first + 1];
  }
  double area(uint32_t i) const { return bin.nodes[i].bounds.half_area(); }
  double as_node(uint32_t i) {
    if (bin.nodes[i].is_leaf()) return std::numeric_limits<double>::infinity();
    double best = std::numeric_limits<double>::infinity();
    for (int j = 1; j < 8; ++j) best = std::min(best, cover(bin.nodes[i].first, j) + cover(bin.nodes[i].first + 1, 8 - j));
    return area(i) + best;
  }
  double one_slot(uint32_t i) {
    const double leaf = count[i] <= 16 ? area(i) * ((count[i] + 3) / 4) : std::numeric_limits<double>::infinity();
    return std::min(leaf, as_node(i));
  }
  double cover(uint32_t i, int k) {
    double& m = memo[i][size_t(k)];
    if (m >= 0.0) return m;
    double best = one_slot(i);
    if (!bin.nodes[i].is_leaf())
      for (int j = 1; j < k; ++j) best = std::min(best, cover(bin.nodes[i].first, j) + cover(bin.nodes[i].first + 1, k - j));
    return m = best;
  }
};

/// The same cost read off the wide tree: each node's box area, and each leaf slot's area times its blocks.
double wide_cost(const Bvh8& w, ChildRef ref) {
  const Bvh8Node& node = w.node(ref);
  AABB box;
  double cost = 0.0;
  for (int s = 0; s < 8; ++s) {
    const ChildRef c = node.child[s];
    if (c == kEmptyChild) continue;
    box.extend(slot_box(node, s));
    cost += is_leaf_ref(c) ? double(slot_box(node, s).half_area()) * leaf_count(c) : wide_cost(w, c);
  }
  return cost + box.half_area();
}

TEST(Bvh8, CollapseReachesTheSahOptimalCover) {
  for (int tubes : {8, 24, 64}) {
    const std::vector<vec3> tv = knot_triangles(tubes * 4, tubes);  // 2 * 4 * tubes^2 triangles
    const Bvh bin = build_triangle_bvh(tv, triangle_build_options({}));
    ASSERT_FALSE(bin.nodes[0].is_leaf());
    const Bvh8 w = make_bvh8(bin, tv, 2);
    ReferenceCollapse ref(bin);
    const double optimal = ref.as_node(0), built = wide_cost(w, 0);
    EXPECT_NEAR(built, optimal, 1e-5 * optimal) << tv.size() / 3 << " triangles";
  }
}

TEST(Bvh8, NonFiniteVerticesNeverHitAndLeaveTheRestIntact) {
  std::vector<vec3> tv = knot_triangles(60, 16);  // 1,920 triangles
  const size_t finite_count = tv.size() / 3;
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), kInfinity, -kInfinity};
  for (int i = 0; i < 30; ++i) {  // 30 more triangles, each with one non-finite coordinate
    vec3 a = tv[3 * size_t(i)], b = tv[3 * size_t(i) + 1], c = tv[3 * size_t(i) + 2];
    c[i % 3] = bad[i % 3];
    tv.insert(tv.end(), {a, b, c});
  }
  TraceGeometry g = make_trace_geometry(tv, {});
  EXPECT_TRUE(is_finite(g.bounds().lo) && is_finite(g.bounds().hi));
  // A refit over the same vertices recomputes the same boxes: the non-finite triangles stay out of them.
  const AABB built = bvh8_bounds(g.triangles);
  refit_bvh8(g.triangles, tv);
  EXPECT_EQ(bvh8_bounds(g.triangles).lo, built.lo);
  EXPECT_EQ(bvh8_bounds(g.triangles).hi, built.hi);
  Pcg32 rng(5, 6);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const AABB b = g.bounds();
    vec3 org = b.center() + 2.0f * glm::length(b.extent()) * sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
    Ray ray{org, glm::normalize(b.lo + rand3(rng) * b.extent() - org), kInfinity};
    const WatertightRay w = make_watertight_ray(ray);
    Hit want;
    want.t = kInfinity;
    bool want_hit = false;
    for (uint32_t t = 0; t < finite_count; ++t) {
      TriangleHit th;
      if (intersect_triangle(w, want.t, tv[3 * t], tv[3 * t + 1], tv[3 * t + 2], th)) want = {th.t, t, 0, 0}, want_hit = true;
    }
    Ray r = ray;
    Hit got;
    ASSERT_EQ(intersect_closest(g, r, got), want_hit) << "ray " << i;
    ASSERT_EQ(intersect_any(g, ray), want_hit) << "ray " << i;
    if (want_hit) {
      ASSERT_LT(got.prim, finite_count);
      ASSERT_LE(std::abs(got.t - want.t), 1e-6f * want.t);
      ++hits;
    }
  }
  EXPECT_GT(hits, 200);
}

/// The primitives the wide tree's leaves reference (valid lanes), in any order.
void collect_prims(const Bvh8& w, ChildRef ref, std::vector<uint32_t>& out) {
  const Bvh8Node& node = w.node(ref);
  for (int s = 0; s < 8; ++s) {
    const ChildRef c = node.child[s];
    if (c == kEmptyChild) continue;
    if (!is_leaf_ref(c)) {
      collect_prims(w, c, out);
      continue;
    }
    for (uint32_t k = 0; k < leaf_count(c); ++k)
      for (uint32_t prim : w.block(leaf_first(c) + k * kBlockUnits).prim)
        if (prim != kInvalidPrim) out.push_back(prim);
  }
}

TEST(Bvh8, NodesOfOverflowingAreaAreNeverLeavesTooBig) {
  // Triangles 1e16 across scattered over [-1e19, 1e19]^3: a box spanning 2e19 has a half area past float's range,
  // so every node above the leaves costs infinity as a leaf and as a node alike. The collapse must still never make
  // a leaf of more than kMaxLeafBlocks blocks (a leaf reference holds 2 bits of count: a bigger one would lose its
  // other triangles): every triangle stays in the tree. (Rays cannot check it here: the watertight triangle test's
  // products overflow float for triangles above about 1e12 across, and 1e19 is already 1e12 per float step.)
  // The second case is flat (z = 0) and spans 6e38: its extent along x overflows to infinity, and infinity times
  // the zero extent along z makes the half area NaN, which no comparison orders.
  struct Case {
    float spread, size;
    bool flat;
  };
  for (const Case& cs : {Case{1e19f, 1e16f, false}, Case{3e38f, 1e36f, true}}) {
    Pcg32 rng(11, 12);
    std::vector<vec3> tv;
    const uint32_t n = 3000;
    for (uint32_t i = 0; i < n; ++i) {
      const vec3 c = (2.0f * rand3(rng) - 1.0f) * cs.spread;
      for (int k = 0; k < 3; ++k) {
        vec3 v = c + (rand3(rng) - 0.5f) * cs.size;
        if (cs.flat) v.z = 0.0f;
        tv.push_back(v);
      }
    }
    const Bvh bin = build_triangle_bvh(tv, triangle_build_options({}));
    ASSERT_FALSE(std::isfinite(bin.nodes[0].bounds.half_area()));
    const Bvh8 w = make_bvh8(bin, tv, 2);
    std::vector<uint32_t> prims;
    collect_prims(w, 0, prims);
    std::sort(prims.begin(), prims.end());
    ASSERT_EQ(prims.size(), n);
    for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(prims[i], i);
  }
}

}  // namespace
}  // namespace pt
