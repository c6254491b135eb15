// The BVH (src/accel/bvh.h, bvh_build.cpp, geometry.cpp) against independent references:
//  - closest and any hits equal a brute-force loop over every primitive with the same primitive tests;
//  - the tree is structurally sound (permutation, tight nested bounds, bounded depth) for edge-case inputs;
//  - the binned SAH build (Wald 2007) is within 10% of a full-sweep SAH build written here and beats median splits;
//  - a refit after moving geometry stays exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <thread>

#include "accel/geometry.h"
#include "accel/sphere.h"
#include "core/rng.h"
#include "core/sampling.h"

namespace pt {
namespace {

struct Soup {
  std::vector<vec3> tris;  ///< three vertices per triangle
  std::vector<SphereShape> spheres;
  uint32_t tri_count() const { return uint32_t(tris.size() / 3); }
  uint32_t prim_count() const { return tri_count() + uint32_t(spheres.size()); }
};

vec3 rand3(Pcg32& rng) { return vec3(rng.next_float(), rng.next_float(), rng.next_float()); }

/// Triangles in [-5,5]^3 of every awkward kind: large, tiny (1e-3), long slivers (4 x 1e-3), exact duplicates,
/// duplicates with rotated vertex order, axis-aligned (flat boxes), degenerate (repeated vertex or exactly
/// collinear); the rest medium. Spheres of radius 1e-3 .. 1.05.
Soup mixed_soup(int n_tris, int n_spheres, uint64_t seed) {
  Pcg32 rng(seed, 1);
  Soup s;
  for (int i = 0; i < n_tris; ++i) {
    const vec3 c = rand3(rng) * 10.0f - 5.0f;
    auto near_c = [&](float size) { return c + size * (rand3(rng) - 0.5f); };
    vec3 a = near_c(0.3f), b = near_c(0.3f), d = near_c(0.3f);
    const int kind = i % 50;
    if (kind == 0) {
      a = near_c(2.0f), b = near_c(2.0f), d = near_c(2.0f);
    } else if (kind <= 4) {
      a = near_c(1e-3f), b = near_c(1e-3f), d = near_c(1e-3f);
    } else if (kind <= 7) {
      vec3 axis = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
      a = c - 2.0f * axis, b = c + 2.0f * axis, d = near_c(1e-3f);
    } else if (kind <= 9 && i >= 10) {
      uint32_t j = uint32_t(i) - 1 - rng.next_u32() % 8;
      a = s.tris[3 * j], b = s.tris[3 * j + 1], d = s.tris[3 * j + 2];
      if (kind == 9) std::swap(a, b), std::swap(b, d);
    } else if (kind <= 11) {
      int k = int(rng.next_u32() % 3);
      b[k] = a[k], d[k] = a[k];
    } else if (kind == 12) {
      if (i % 100 == 12) {
        d = b;
      } else {
        int k = int(rng.next_u32() % 3);
        b = a, d = a;
        b[k] += 0.25f, d[k] -= 0.125f;
      }
    }
    s.tris.insert(s.tris.end(), {a, b, d});
  }
  for (int i = 0; i < n_spheres; ++i)
    s.spheres.push_back({rand3(rng) * 10.0f - 5.0f, i % 10 == 0 ? 1e-3f : 0.05f + rng.next_float()});
  return s;
}

/// Uniform soup in [0,1]^3 of triangles about 0.04 across, for the SAH comparison.
Soup uniform_soup(int n_tris, uint64_t seed) {
  Pcg32 rng(seed, 3);
  Soup s;
  for (int i = 0; i < n_tris; ++i) {
    vec3 c = rand3(rng);
    for (int k = 0; k < 3; ++k) s.tris.push_back(c + 0.04f * (rand3(rng) - 0.5f));
  }
  return s;
}

std::vector<AABB> prim_boxes(const Soup& s) {
  std::vector<AABB> boxes;
  for (uint32_t i = 0; i < s.tri_count(); ++i) {
    AABB b;
    for (int k = 0; k < 3; ++k) b.extend(s.tris[3 * i + k]);
    boxes.push_back(b);
  }
  for (const SphereShape& sp : s.spheres) boxes.push_back(sp.bounds());
  return boxes;
}

std::vector<vec3> box_centers(const std::vector<AABB>& boxes) {
  std::vector<vec3> c;
  for (const AABB& b : boxes) c.push_back(b.center());
  return c;
}

/// The reference: every primitive in id order through the same intersect_triangle / intersect_sphere. A bounding
/// sphere cull (radius x 1.41 plus ~5e-5 of the coordinate magnitudes, far above float rounding) only skips
/// primitives whose exact test cannot hit; `cull = false` checks that on a subset of rays.
struct BruteForce {
  const Soup& s;
  std::vector<float> x, y, z, lim;  ///< bounding sphere centers; 2 r^2 + 3e-9 |c|^2

  explicit BruteForce(const Soup& soup) : s(soup) {
    for (const AABB& b : prim_boxes(s)) {
      vec3 c = b.center(), h = 0.5f * b.extent();
      x.push_back(c.x), y.push_back(c.y), z.push_back(c.z);
      lim.push_back(2.0f * glm::dot(h, h) + 3e-9f * glm::dot(c, c));
    }
  }

  bool test(uint32_t i, const Ray& ray, const WatertightRay& w, Hit& best) const {
    if (i < s.tri_count()) {
      TriangleHit th;
      if (!intersect_triangle(w, best.t, s.tris[3 * i], s.tris[3 * i + 1], s.tris[3 * i + 2], th)) return false;
      best = {th.t, i, th.b1, th.b2};
      return true;
    }
    const SphereShape& sp = s.spheres[i - s.tri_count()];
    float t = intersect_sphere(ray, sp.center, sp.radius, best.t);
    if (!(t < best.t)) return false;
    best = {t, i, 0.0f, 0.0f};
    return true;
  }

  /// `mask` is scratch space (one per thread).
  bool closest(const Ray& ray, Hit& best, std::vector<uint8_t>& mask, bool cull = true) const {
    const WatertightRay w = make_watertight_ray(ray);
    best = Hit{};
    best.t = ray.tmax;
    bool found = false;
    const uint32_t n = uint32_t(x.size());
    if (!cull) {
      for (uint32_t i = 0; i < n; ++i) found |= test(i, ray, w, best);
      return found;
    }
    mask.resize(n);
    // |f x d|^2 <= |d|^2 (2 r^2 + 3e-9 (|c|^2 + |o|^2)), f = c - o: vectorizes (no branches).
    const vec3 o = ray.org, d = ray.dir;
    const float d2 = glm::dot(d, d), o_term = 3e-9f * glm::dot(o, o);
    for (uint32_t i = 0; i < n; ++i) {
      float fx = x[i] - o.x, fy = y[i] - o.y, fz = z[i] - o.z;
      float cx = fy * d.z - fz * d.y, cy = fz * d.x - fx * d.z, cz = fx * d.y - fy * d.x;
      mask[i] = cx * cx + cy * cy + cz * cz <= d2 * (lim[i] + o_term);
    }
    for (uint32_t i = 0; i < n; ++i)
      if (mask[i]) found |= test(i, ray, w, best);
    return found;
  }
};

/// Offsets of the wide tree's nodes, root first, each after its parent.
std::vector<ChildRef> wide_nodes(const Bvh8& w) {
  std::vector<ChildRef> out;
  if (w.empty()) return out;
  out.push_back(0);
  for (size_t k = 0; k < out.size(); ++k)
    for (ChildRef c : w.node(out[k]).child)
      if (c != kEmptyChild && !is_leaf_ref(c)) out.push_back(c);
  return out;
}

/// Every box of the wide triangle tree's slots and of the sphere tree's nodes: planes rays are aimed along.
std::vector<AABB> node_boxes(const TraceGeometry& g) {
  std::vector<AABB> boxes;
  for (ChildRef n : wide_nodes(g.triangles))
    for (int i = 0; i < 8; ++i)
      if (g.triangles.node(n).child[i] != kEmptyChild) boxes.push_back(slot_box(g.triangles.node(n), i));
  for (const BvhNode& node : g.sphere_bvh.nodes) boxes.push_back(node.bounds);
  return boxes;
}

void check_structure(const Bvh& bvh, const std::vector<AABB>& boxes, int max_leaf);

/// The wide tree: every triangle in exactly one lane of one leaf block, every node and block reached once from the
/// root and stored after its parent, nodes and blocks tiling the arena, every slot box equal to the union of what it
/// holds, padding lanes marked, leaf sizes within the limit. The sphere tree: check_structure.
void check_trace_structure(const TraceGeometry& g, const Soup& s) {
  const Bvh8& w = g.triangles;
  ASSERT_EQ(g.triangle_count, s.tri_count());
  std::vector<int> seen(s.tri_count(), 0), unit_owner(w.units.size(), 0);
  auto claim = [&](uint32_t first, uint32_t units) {
    ASSERT_LE(size_t(first) + units, w.units.size());
    for (uint32_t u = first; u < first + units; ++u) ASSERT_EQ(unit_owner[u]++, 0) << "unit " << u << " reused";
  };
  auto tri_box = [&](uint32_t p) {
    AABB b;
    for (int k = 0; k < 3; ++k) b.extend(s.tris[3 * size_t(p) + k]);
    return b;
  };
  size_t nodes = 0, blocks = 0;
  std::vector<uint32_t> stack;
  if (!w.empty()) stack.push_back(0), claim(0, kNodeUnits);
  while (!stack.empty()) {
    const uint32_t n = stack.back();
    stack.pop_back();
    ++nodes;
    const Bvh8Node& node = w.node(n);
    for (int i = 0; i < 8; ++i) {
      const ChildRef ref = node.child[i];
      const AABB slot = slot_box(node, i);
      if (ref == kEmptyChild) {
        EXPECT_TRUE(slot.empty());
        continue;
      }
      AABB content;
      if (is_leaf_ref(ref)) {
        EXPECT_LE(leaf_count(ref), kMaxLeafBlocks) << "leaves hold at most 16 triangles (the collapse may merge leaves)";
        ASSERT_GT(leaf_first(ref), n) << "a leaf comes after its parent";
        claim(leaf_first(ref), leaf_count(ref) * kBlockUnits);
        for (uint32_t k = 0; k < leaf_count(ref); ++k) {
          ++blocks;
          const Tri4& blk = w.block(leaf_first(ref) + k * kBlockUnits);
          ASSERT_NE(blk.prim[0], kInvalidPrim);
          for (int lane = 0; lane < 4; ++lane) {
            if (blk.prim[lane] == kInvalidPrim) {
              // A padding lane repeats lane 0, so whatever it hits, lane 0 hits at the same t (bvh8.h).
              for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a) ASSERT_EQ(blk.v[v][a][lane], blk.v[v][a][0]) << "padding lane " << lane;
              continue;
            }
            ASSERT_LT(blk.prim[lane], s.tri_count());
            seen[blk.prim[lane]]++;
            content.extend(tri_box(blk.prim[lane]));
            for (int v = 0; v < 3; ++v)
              for (int a = 0; a < 3; ++a) ASSERT_EQ(blk.v[v][a][lane], s.tris[3 * size_t(blk.prim[lane]) + v][a]);
          }
        }
      } else {
        ASSERT_GT(ref, n) << "a child comes after its parent";
        claim(ref, kNodeUnits);
        stack.push_back(ref);
        const Bvh8Node& c = w.node(ref);
        for (int j = 0; j < 8; ++j)
          if (c.child[j] != kEmptyChild) content.extend(slot_box(c, j));
      }
      EXPECT_EQ(slot.lo, content.lo);
      EXPECT_EQ(slot.hi, content.hi);
    }
  }
  for (uint32_t p = 0; p < s.tri_count(); ++p) ASSERT_EQ(seen[p], 1) << "triangle " << p;
  for (size_t u = 0; u < unit_owner.size(); ++u) ASSERT_EQ(unit_owner[u], 1) << "unit " << u << " unused";
  EXPECT_EQ(nodes, w.node_count);
  EXPECT_EQ(blocks, w.block_count);
  Soup only_spheres;
  only_spheres.spheres = s.spheres;
  check_structure(g.sphere_bvh, prim_boxes(only_spheres), 8);
  for (size_t k = 0; k < g.spheres.size(); ++k)
    EXPECT_EQ(g.spheres[k].prim, s.tri_count() + g.sphere_bvh.prim_indices[k]);
  // The bounds of both trees together, exactly (the viewer's unit of length, camera_control.h scene_size).
  AABB all;
  for (uint32_t p = 0; p < s.tri_count(); ++p) all.extend(finite_or_empty(tri_box(p)));
  for (const SphereShape& sp : s.spheres) all.extend(finite_or_empty(sp.bounds()));
  EXPECT_EQ(g.bounds().lo, all.lo);
  EXPECT_EQ(g.bounds().hi, all.hi);
}

/// Rays of every kind a traversal can get wrong, by i % 10: far-away origins aimed at the scene; directions with
/// two or one exact zero components; origins exactly on a BVH node's face plane (half of them moving inside that
/// plane, so the slab test sees 0 * inf); rays lying in an axis plane through a triangle vertex, aimed at it;
/// otherwise random origins in [-7,7]^3 (inside and outside the scene bounds) and random directions.
Ray make_test_ray(Pcg32& rng, int i, const Soup& s, const std::vector<AABB>& boxes) {
  auto u = [&] { return rng.next_float(); };
  vec3 o = rand3(rng) * 14.0f - 7.0f;
  vec3 d = sample_uniform_sphere(vec2(u(), u()));
  const int k = int(rng.next_u32() % 3);
  switch (i % 10) {
    case 0:
      o = (40.0f + 20.0f * u()) * sample_uniform_sphere(vec2(u(), u()));
      d = glm::normalize(rand3(rng) * 10.0f - 5.0f - o);
      break;
    case 1:
      d = vec3(0.0f);
      d[k] = u() < 0.5f ? 1.0f : -1.0f;
      break;
    case 2:
      d[k] = 0.0f;
      d = glm::normalize(d);
      break;
    case 3:
    case 4: {
      const AABB box = boxes.empty() ? AABB{} : boxes[rng.next_u32() % boxes.size()];
      if (box.empty()) break;
      o[k] = u() < 0.5f ? box.lo[k] : box.hi[k];
      if (i % 10 == 3) d[k] = 0.0f, d = glm::normalize(d);
      break;
    }
    case 5: {
      if (s.tris.empty()) break;
      vec3 v = s.tris[rng.next_u32() % s.tris.size()];
      d[k] = 0.0f;
      d = glm::normalize(d);
      o = v - (1.0f + 5.0f * u()) * d;
      o[k] = v[k];
      break;
    }
    default:
      break;
  }
  return Ray{o, d, kInfinity};
}

/// Compares intersect_closest and intersect_any with the brute force on n_rays rays; a third get a finite tmax,
/// some of them exactly the closest hit distance or one float either side of it.
void expect_matches_brute_force(const TraceGeometry& g, const Soup& s, int n_rays, uint64_t seed,
                                int min_hit_percent) {
  ASSERT_EQ(g.primitive_count(), size_t(s.prim_count()));
  const BruteForce brute(s);
  Pcg32 rng(seed, 5);
  std::vector<Ray> rays(static_cast<size_t>(n_rays));
  std::vector<int> tmax_mode(rays.size(), 0);
  const std::vector<AABB> boxes = node_boxes(g);
  for (int i = 0; i < n_rays; ++i) {
    rays[i] = make_test_ray(rng, i, s, boxes);
    if (i % 3 == 1) rays[i].tmax = rng.next_float() * 12.0f;
    if (i % 6 == 2) tmax_mode[i] = 1 + int(rng.next_u32() % 3);
  }
  // The brute force is the slow part: two threads, each on every other ray.
  std::vector<Hit> expected(rays.size());
  std::vector<uint8_t> expected_hit(rays.size()), cull_ok(rays.size(), 1);
  auto run = [&](int part) {
    std::vector<uint8_t> mask;
    for (size_t i = size_t(part); i < rays.size(); i += 2) {
      Hit h;
      if (tmax_mode[i] && brute.closest(rays[i], h, mask)) {
        rays[i].tmax = tmax_mode[i] == 1 ? h.t : (tmax_mode[i] == 2 ? next_float_up(h.t) : next_float_down(h.t));
      }
      expected_hit[i] = brute.closest(rays[i], expected[i], mask);
      if (i < 1000) {
        bool f = brute.closest(rays[i], h, mask, false);
        cull_ok[i] = f == bool(expected_hit[i]) && (!f || (h.t == expected[i].t && h.prim == expected[i].prim));
      }
    }
  };
  std::thread worker(run, 1);
  run(0);
  worker.join();

  int hits = 0, sphere_hits = 0, ties = 0, bad_closest = 0, bad_any = 0, bad_cull = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    const bool e = expected_hit[i];
    bad_cull += !cull_ok[i];
    Ray r = ray;
    Hit got;
    const bool h = intersect_closest(g, r, got);
    const bool any = intersect_any(g, ray);
    if (any != e && ++bad_any <= 5)
      ADD_FAILURE() << "ray " << i << ": intersect_any " << any << " brute " << e << " tmax " << ray.tmax;
    if (!e && !h) continue;
    bool ok = h == e;
    if (ok && got.prim == expected[i].prim) {
      ok = got.t == expected[i].t && r.tmax == got.t;
    } else if (ok) {
      // Coincident primitives: either is right if the other one really hits within 1e-6 relative.
      Hit check;
      check.t = ray.tmax;
      ok = brute.test(got.prim, ray, make_watertight_ray(ray), check) && check.t == got.t &&
           std::abs(got.t - expected[i].t) <= 1e-6f * expected[i].t;
      ties += ok;
    }
    if (!ok && ++bad_closest <= 5)
      ADD_FAILURE() << "ray " << i << " org " << ray.org.x << "," << ray.org.y << "," << ray.org.z << " dir "
                    << ray.dir.x << "," << ray.dir.y << "," << ray.dir.z << " tmax " << ray.tmax << ": bvh " << h
                    << " prim " << got.prim << " t " << got.t << ", brute " << e << " prim " << expected[i].prim
                    << " t " << expected[i].t;
    hits += e;
    sphere_hits += e && expected[i].prim >= s.tri_count();
  }
  EXPECT_EQ(bad_closest, 0) << "closest-hit mismatches of " << n_rays;
  EXPECT_EQ(bad_any, 0) << "any-hit mismatches of " << n_rays;
  EXPECT_EQ(bad_cull, 0) << "the brute-force cull skipped a hit";
  // The comparison means something only if many rays hit, some of them spheres.
  EXPECT_GE(hits * 100, min_hit_percent * n_rays) << hits << " hits";
  if (!s.spheres.empty()) {
    EXPECT_GT(sphere_hits, 0);
  }
  ::testing::Test::RecordProperty("ties", ties);
}

TEST(Bvh, ClosestAndAnyHitEqualBruteForce) {
  Soup s = mixed_soup(20000, 40, 1);
  TraceGeometry g = make_trace_geometry(s.tris, s.spheres);
  expect_matches_brute_force(g, s, 100000, 2, 30);
}

// A few spheres (at most kFlatSpheres, accel/geometry.cpp) are tested one by one instead of through their tree.
TEST(Bvh, FewSpheresWithoutTheirTreeEqualBruteForce) {
  Soup s = mixed_soup(5000, 6, 3);
  TraceGeometry g = make_trace_geometry(s.tris, s.spheres);
  expect_matches_brute_force(g, s, 100000, 4, 10);
}

// REGRESSION TEST for a bug this suite found (src/accel/bvh.h intersect_box): a hit at t must be found when tmax is
// one float above t. The triangle lies in z = 0, so the root box is flat in z and its slab entry distance
// (0 - o.z) * inv_dir.z rounds to 1.80722082, two floats above the triangle's t = 1.80722058; a slab test that
// compares it with the unwidened tmax culls the root. Widening tmax by the same 1 + 2 gamma(3) factor Ize 2013
// applies to the far distances fixes it. ClosestAndAnyHitEqualBruteForce found the same case in the mixed soup.
TEST(Bvh, FiniteTmaxOneFloatBeyondAHitOnAFlatBoxStillHits) {
  const std::vector<vec3> tri = {vec3(-1, -1, 0), vec3(1, -1, 0), vec3(0, 1, 0)};
  TraceGeometry g = make_trace_geometry(tri, {});
  Ray ray{vec3(0x1.73064p-2f, -0x1.bd39bp+0f, 0x1.342506p+0f), vec3(-0x1.14cb1p-3f, 0x1.7795dep-1f, -0x1.5503d2p-1f)};
  TriangleHit th;
  ASSERT_TRUE(intersect_triangle(make_watertight_ray(ray), kInfinity, tri[0], tri[1], tri[2], th));
  ray.tmax = next_float_up(th.t);
  EXPECT_TRUE(intersect_any(g, ray)) << "hit at t = " << th.t << " missed with tmax = " << ray.tmax;
  Hit hit;
  EXPECT_TRUE(intersect_closest(g, ray, hit));
}

// The binary tree's slab test (bvh.h intersect_box, used by the sphere tree): a ray through a point of a box's edge
// touches the closed box, so it must not be culled; in exact arithmetic its entry and exit distances are equal
// there, and only the widening of the far distances by 1 + 2 gamma(3) (Ize 2013) keeps their roundings from
// crossing. Coordinates are multiples of 1/8 below 16, so the direction q - o is exact and the ray passes exactly
// through q.
TEST(Bvh, SlabTestKeepsRaysThroughABoxEdge) {
  Pcg32 rng(11, 3);
  auto grid = [&](float lo, float hi) { return lo + std::floor(rng.next_float() * (hi - lo) * 8.0f) / 8.0f; };
  int missed = 0, cases = 0;
  for (int i = 0; i < 200000; ++i) {
    AABB box{vec3(grid(-4, 0), grid(-4, 0), grid(-4, 0)), vec3(grid(0.125f, 4), grid(0.125f, 4), grid(0.125f, 4))};
    vec3 q(grid(box.lo.x, box.hi.x), grid(box.lo.y, box.hi.y), grid(box.lo.z, box.hi.z));
    const int a = int(rng.next_u32() % 3), b = (a + 1 + int(rng.next_u32() % 2)) % 3;
    q[a] = rng.next_u32() & 1 ? box.hi[a] : box.lo[a];  // on two faces at once: an edge
    q[b] = rng.next_u32() & 1 ? box.hi[b] : box.lo[b];
    const vec3 o(grid(-12, 12), grid(-12, 12), grid(-12, 12));
    if (o == q) continue;
    ++cases;
    const Ray ray{o, q - o, kInfinity};
    if (intersect_box(box, make_ray_box_data(ray), kInfinity) == kInfinity) ++missed;
  }
  EXPECT_GT(cases, 190000);
  EXPECT_EQ(missed, 0) << "of " << cases << " rays through a box edge";
}

// The SAH charges a leaf for the SIMD blocks it fills: a leaf of 5 triangles costs two 4-wide tests, like one of 8.
TEST(Bvh, LeafCostCountsWholeBlocks) {
  BvhBuildOptions o;
  o.leaf_block_size = 4;
  const float expected[] = {0, 4, 4, 4, 4, 8, 8, 8, 8, 12};
  for (uint32_t n = 0; n < 10; ++n) EXPECT_EQ(sah_leaf_tests(n, o), expected[n]) << n;
  o.leaf_block_size = 1;
  EXPECT_EQ(sah_leaf_tests(7, o), 7.0f);
  o.leaf_block_size = 0;  // no blocks: one test per primitive
  EXPECT_EQ(sah_leaf_tests(7, o), 7.0f);
}

// A direction component of -0 is a direction parallel to that slab, like +0: the ray inside the slab hits.
TEST(Bvh, SlabTestTakesNegativeZeroDirectionsAsParallel) {
  const AABB box{vec3(-1.0f), vec3(1.0f)};
  for (float zero : {0.0f, -0.0f}) {
    for (int axis = 0; axis < 3; ++axis) {
      vec3 d(zero);
      d[(axis + 1) % 3] = 1.0f;
      vec3 o(0.0f);
      o[(axis + 1) % 3] = -5.0f;
      EXPECT_EQ(intersect_box(box, make_ray_box_data(Ray{o, d, kInfinity}), kInfinity), 4.0f) << zero << " " << axis;
      o[axis] = 2.0f;  // outside the slab of the parallel axis: a miss
      EXPECT_EQ(intersect_box(box, make_ray_box_data(Ray{o, d, kInfinity}), kInfinity), kInfinity) << zero;
    }
  }
}

/// Depth-first walk checking every structural invariant against the primitive boxes the tree was built from.
void check_structure(const Bvh& bvh, const std::vector<AABB>& boxes, int max_leaf) {
  const size_t n = boxes.size();
  ASSERT_EQ(bvh.prim_indices.size(), n);
  ASSERT_EQ(bvh.nodes.empty(), n == 0);
  if (n == 0) return;
  std::vector<int> seen(n, 0);
  for (uint32_t p : bvh.prim_indices) {
    ASSERT_LT(p, n);
    seen[p]++;
  }
  for (size_t p = 0; p < n; ++p) ASSERT_EQ(seen[p], 1) << "primitive " << p;
  std::vector<int> covered(n, 0), visits(bvh.nodes.size(), 0);
  struct Item { uint32_t node; int depth; };
  std::vector<Item> stack{{0, 0}};
  int max_depth = 0;
  auto contains = [](const AABB& outer, const AABB& inner) {
    return glm::all(glm::lessThanEqual(outer.lo, inner.lo)) && glm::all(glm::greaterThanEqual(outer.hi, inner.hi));
  };
  while (!stack.empty()) {
    Item it = stack.back();
    stack.pop_back();
    ASSERT_LT(it.node, bvh.nodes.size());
    ASSERT_EQ(visits[it.node]++, 0) << "node " << it.node << " reached twice";
    max_depth = std::max(max_depth, it.depth);
    const BvhNode& node = bvh.nodes[it.node];
    AABB tight;
    if (node.is_leaf()) {
      ASSERT_LE(node.count, uint32_t(max_leaf)) << "leaf above max_leaf_size";
      ASSERT_LE(size_t(node.first) + node.count, n);
      for (uint32_t k = node.first; k < node.first + node.count; ++k) {
        covered[k]++;
        const AABB& b = boxes[bvh.prim_indices[k]];
        ASSERT_TRUE(contains(node.bounds, b)) << "leaf " << it.node << " does not contain primitive box";
        tight.extend(b);
      }
    } else {
      for (uint32_t c : {node.first, node.first + 1}) {
        ASSERT_LT(c, bvh.nodes.size());
        ASSERT_GT(c, it.node) << "children must follow their parent (refit sweeps in reverse)";
        ASSERT_TRUE(contains(node.bounds, bvh.nodes[c].bounds)) << "node " << it.node << " child " << c;
        tight.extend(bvh.nodes[c].bounds);
        stack.push_back({c, it.depth + 1});
      }
    }
    ASSERT_TRUE(node.bounds.lo == tight.lo && node.bounds.hi == tight.hi) << "node " << it.node << " not tight";
  }
  for (size_t k = 0; k < n; ++k) ASSERT_EQ(covered[k], 1) << "leaf ranges must partition prim_indices";
  for (size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i], 1) << "node " << i << " unreachable";
  EXPECT_EQ(bvh.depth, max_depth);
  EXPECT_LE(max_depth, kBvhMaxDepth);
}

TEST(Bvh, StructureIsSoundForTinyInputs) {
  for (int n : {0, 1, 2, 3}) {
    Soup s = mixed_soup(n, 0, 10 + uint64_t(n));
    std::vector<AABB> boxes = prim_boxes(s);
    check_structure(build_bvh(boxes), boxes, 8);
    TraceGeometry g = make_trace_geometry(s.tris, s.spheres);
    check_trace_structure(g, s);
    expect_matches_brute_force(g, s, 3000, 20 + uint64_t(n), 0);
  }
  Soup one_sphere;
  one_sphere.spheres.push_back({vec3(0.5f), 2.0f});
  TraceGeometry g = make_trace_geometry({}, one_sphere.spheres);
  check_trace_structure(g, one_sphere);
  expect_matches_brute_force(g, one_sphere, 3000, 30, 2);
}

TEST(Bvh, IdenticalTrianglesKeepDepthBoundedAndHit) {
  Soup s;
  for (int i = 0; i < 10000; ++i) s.tris.insert(s.tris.end(), {vec3(-1, -1, 0), vec3(1, -1, 0), vec3(0, 1, 0)});
  TraceGeometry g = make_trace_geometry(s.tris, {});
  check_trace_structure(g, s);
  EXPECT_LE(g.stats.depth, 12);  // median splits: ceil(log2(10000 / 8)) = 11
  Ray ray{vec3(0.1f, 0.2f, 3.0f), vec3(0, 0, -1), kInfinity};
  Hit hit;
  ASSERT_TRUE(intersect_closest(g, ray, hit));
  EXPECT_FLOAT_EQ(hit.t, 3.0f);
  EXPECT_LT(hit.prim, 10000u);
  expect_matches_brute_force(g, s, 3000, 40, 0);
}

// A leaf of the wide tree holds at most kMaxLeafBlocks blocks of 4, whatever leaf size the options ask for: the
// binary build is held to that limit (triangle_build_options), so many identical triangles, which only median
// splits can part, still end in leaves the wide tree can hold. A leaf size below one is taken as one.
TEST(Bvh, TheLeafSizeAskedForIsHeldToWhatAWideLeafHolds) {
  Soup s;
  for (int i = 0; i < 200; ++i) s.tris.insert(s.tris.end(), {vec3(-1, -1, 0), vec3(1, -1, 0), vec3(0, 1, 0)});
  for (int leaf : {1000, 17, 0, -5}) {
    BvhBuildOptions options;
    options.max_leaf_size = leaf;
    EXPECT_EQ(triangle_build_options(options).max_leaf_size, std::clamp(leaf, 1, 4 * int(kMaxLeafBlocks)));
    TraceGeometry g = make_trace_geometry(s.tris, {}, options);
    check_trace_structure(g, s);
    expect_matches_brute_force(g, s, 2000, 50, 0);
  }
}

// The memory figure (stats JSON "bvh.bytes") counts what traversal reads of both trees: spheres add their tree and
// their data to the triangles' bytes.
TEST(Bvh, TheMemoryFigureCountsTheSpheres) {
  const Soup s = mixed_soup(300, 40, 12);
  const TraceGeometry a = make_trace_geometry(s.tris, {}), b = make_trace_geometry(s.tris, s.spheres);
  EXPECT_EQ(a.stats.memory_bytes, a.triangles.bytes());
  EXPECT_GE(b.stats.memory_bytes,
            b.triangles.bytes() + 40 * sizeof(TraceGeometry::Sphere) + (2 * 40 - 1) * sizeof(BvhNode));
}

TEST(Bvh, CollinearAndGeometricCentroidsKeepDepthBounded) {
  // Triangles with centroids on a diagonal line: structure and traversal.
  Soup line;
  for (int i = 0; i < 10000; ++i) {
    vec3 c(float(i) * 1e-3f - 5.0f);
    line.tris.insert(line.tris.end(), {c + vec3(0.2f, 0, 0), c + vec3(-0.1f, 0.2f, 0), c + vec3(-0.1f, -0.2f, 0.1f)});
  }
  TraceGeometry g = make_trace_geometry(line.tris, {});
  check_trace_structure(g, line);
  expect_matches_brute_force(g, line, 3000, 50, 1);
  // Boxes with centroids on an axis, then spaced geometrically over 30 orders of magnitude (an SAH build peels off
  // a few primitives per level), with leaves of up to 8 and of 1.
  std::vector<std::vector<AABB>> cases(2);
  for (int i = 0; i < 10000; ++i) cases[0].push_back({vec3(float(i) * 0.01f, 0, 0), vec3(float(i) * 0.01f + 0.5f, 1, 1)});
  for (int i = 0; i < 3000; ++i) {
    float x = std::ldexp(1.0f, i / 30 - 50) * (1.0f + float(i % 30) / 30.0f);
    cases[1].push_back({vec3(x, 0, 0), vec3(1.5f * x, x, x)});
  }
  for (const auto& boxes : cases) {
    for (int leaf : {1, 8}) {
      BvhBuildOptions o;
      o.max_leaf_size = leaf;
      check_structure(build_bvh(boxes, o), boxes, leaf);
    }
  }
}

/// SAH cost recomputed from the primitive boxes (not node.bounds), in the normalization sah_cost documents.
double reference_sah(const Bvh& bvh, const std::vector<AABB>& boxes, double traversal_cost) {
  double cost = 0.0;
  auto subtree = [&](auto&& self, uint32_t index) -> AABB {
    const BvhNode& node = bvh.nodes[index];
    AABB b;
    if (node.is_leaf()) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) b.extend(boxes[bvh.prim_indices[k]]);
      cost += double(b.half_area()) * node.count;
    } else {
      b = merge(self(self, node.first), self(self, node.first + 1));
      cost += double(b.half_area()) * traversal_cost;
    }
    return b;
  };
  AABB root = subtree(subtree, 0);
  return cost / double(root.half_area());
}

/// Top-down builders written independently of bvh_build.cpp, on the same node layout: a greedy full-sweep SAH
/// (every split position along every axis, from sorting: the quality binning approximates; Wald 2007 section 3)
/// with the same leaf criterion, and an object-median split along the widest centroid axis.
struct ReferenceBuilder {
  const std::vector<AABB>& boxes;
  std::vector<vec3> centers;
  BvhBuildOptions options;
  bool sweep;
  Bvh bvh;

  void build(uint32_t index, uint32_t begin, uint32_t end, int depth) {
    bvh.depth = std::max(bvh.depth, depth);
    auto first = bvh.prim_indices.begin() + begin, last = bvh.prim_indices.begin() + end;
    const uint32_t count = end - begin;
    AABB bounds, cbounds;
    for (auto it = first; it != last; ++it) bounds.extend(boxes[*it]), cbounds.extend(centers[*it]);
    bvh.nodes[index].bounds = bounds;
    auto by_axis = [&](int axis) {
      std::sort(first, last, [&](uint32_t a, uint32_t b) {
        return centers[a][axis] < centers[b][axis] || (centers[a][axis] == centers[b][axis] && a < b);
      });
    };
    uint32_t mid = count / 2;
    if (count == 1 || (!sweep && count <= uint32_t(options.max_leaf_size))) {
      bvh.nodes[index].first = begin, bvh.nodes[index].count = count;
      return;
    }
    if (sweep) {
      double best = 1e300;
      int best_axis = 0;
      std::vector<double> right(count);
      for (int axis = 0; axis < 3; ++axis) {
        by_axis(axis);
        AABB acc;
        for (uint32_t i = count; i-- > 1;) {
          acc.extend(boxes[*(first + i)]);
          right[i] = double(acc.half_area()) * (count - i);
        }
        acc = AABB{};
        for (uint32_t i = 0; i + 1 < count; ++i) {
          acc.extend(boxes[*(first + i)]);
          double c = double(acc.half_area()) * (i + 1) + right[i + 1];
          if (c < best) best = c, best_axis = axis, mid = i + 1;
        }
      }
      double leaf_cost = double(bounds.half_area()) * count;
      double split_cost = options.traversal_cost * double(bounds.half_area()) + best;
      if (count <= uint32_t(options.max_leaf_size) && leaf_cost <= split_cost) {
        bvh.nodes[index].first = begin, bvh.nodes[index].count = count;
        return;
      }
      by_axis(best_axis);
    } else {
      by_axis(max_dimension(cbounds.extent()));
    }
    uint32_t left = uint32_t(bvh.nodes.size());
    bvh.nodes[index].first = left;
    bvh.nodes.resize(bvh.nodes.size() + 2);
    build(left, begin, begin + mid, depth + 1);
    build(left + 1, begin + mid, end, depth + 1);
  }

  static Bvh make(const std::vector<AABB>& boxes, const BvhBuildOptions& options, bool sweep) {
    ReferenceBuilder b{boxes, box_centers(boxes), options, sweep, {}};
    b.bvh.prim_indices.resize(boxes.size());
    std::iota(b.bvh.prim_indices.begin(), b.bvh.prim_indices.end(), 0u);
    b.bvh.nodes.resize(1);
    b.build(0, 0, uint32_t(boxes.size()), 0);
    return b.bvh;
  }
};

// The full-sweep builder (bvh_sweep.cpp) is the reference the binned one is measured against (here, in test_bvh8
// and in bench_raycast), so it must make a sound tree too: on scattered triangles, and on 1000 copies of one box,
// where every split costs the same, the sweep takes the first (one box peeled off per level), and only its depth
// bound keeps the tree within the traversal stack (check_structure also compares the depth the build records).
TEST(Bvh, TheSweepBuildIsSoundAndBoundedInDepth) {
  const std::vector<std::vector<AABB>> cases = {prim_boxes(uniform_soup(2000, 7)),
                                                std::vector<AABB>(1000, AABB{vec3(0.0f), vec3(1.0f)})};
  for (const auto& boxes : cases) {
    for (int leaf : {1, 8}) {
      BvhBuildOptions o;
      o.max_leaf_size = leaf;
      const Bvh bvh = build_bvh_sweep(boxes, box_centers(boxes), o);
      check_structure(bvh, boxes, leaf);
      EXPECT_GT(bvh.depth, 8);
    }
  }
}

TEST(Bvh, BinnedSahIsWithinTenPercentOfFullSweepAndBeatsMedian) {
  for (const Soup& s : {uniform_soup(5000, 42), mixed_soup(5000, 0, 43)}) {
    std::vector<AABB> boxes = prim_boxes(s);
    BvhBuildOptions opts;
    Bvh binned = build_bvh(boxes, opts);
    for (int leaf : {1, 4, 16}) {
      BvhBuildOptions o;
      o.max_leaf_size = leaf;
      check_structure(build_bvh(boxes, o), boxes, leaf);
    }
    Bvh sweep = ReferenceBuilder::make(boxes, opts, true);
    Bvh median = ReferenceBuilder::make(boxes, opts, false);
    check_structure(binned, boxes, opts.max_leaf_size);
    check_structure(sweep, boxes, opts.max_leaf_size);
    check_structure(median, boxes, opts.max_leaf_size);
    const double c_binned = reference_sah(binned, boxes, opts.traversal_cost);
    const double c_sweep = reference_sah(sweep, boxes, opts.traversal_cost);
    const double c_median = reference_sah(median, boxes, opts.traversal_cost);
    // sah_cost must compute the documented quantity.
    for (const Bvh* b : {&binned, &sweep, &median})
      EXPECT_NEAR(sah_cost(*b, opts.traversal_cost), reference_sah(*b, boxes, opts.traversal_cost),
                  1e-4 * reference_sah(*b, boxes, opts.traversal_cost));
    EXPECT_LE(c_binned, 1.10 * c_sweep) << "binned " << c_binned << " sweep " << c_sweep;
    EXPECT_LT(c_binned, c_median) << "binned " << c_binned << " median " << c_median;
  }
}

/// Primitives in the subtree of binary node `index`.
uint32_t subtree_prims(const Bvh& bvh, uint32_t index) {
  const BvhNode& n = bvh.nodes[index];
  return n.is_leaf() ? n.count : subtree_prims(bvh, n.first) + subtree_prims(bvh, n.first + 1);
}

/// Unit boxes in a row along x, 2 apart (centroids 0, 2, 4, ...): every split of the row is a clean cut.
std::vector<AABB> box_row(int n) {
  std::vector<AABB> boxes;
  for (int i = 0; i < n; ++i) boxes.push_back({vec3(2.0f * i - 0.5f, -0.5f, -0.5f), vec3(2.0f * i + 0.5f, 0.5f, 0.5f)});
  return boxes;
}

TEST(Bvh, BinnedBuilderMakesALeafWhereNoSplitPays) {
  // Two clusters of 4 unit cubes, the second shifted by d along x. Union half area 3 + 2d, each cluster's 3: a
  // leaf of 8 costs 8 (3 + 2d), the best split 24 plus one node visit of 3 + 2d. The leaf pays for d <= 3/14.
  auto clusters = [](float d) {
    std::vector<AABB> boxes;
    for (int i = 0; i < 8; ++i) {
      const float x = i < 4 ? 0.0f : d;
      boxes.push_back({vec3(x, 0.0f, 0.0f), vec3(x + 1.0f, 1.0f, 1.0f)});
    }
    return boxes;
  };
  BvhBuildOptions o;  // traversal cost 1, leaves of up to 8, blocks of 1
  const Bvh leaf = build_bvh(clusters(0.1f), o);
  ASSERT_EQ(leaf.nodes.size(), 1u);
  EXPECT_EQ(leaf.nodes[0].count, 8u);
  const Bvh split = build_bvh(clusters(0.3f), o);
  ASSERT_EQ(split.nodes.size(), 3u);
  EXPECT_EQ(split.nodes[1].count, 4u);
  EXPECT_EQ(split.nodes[2].count, 4u);
  o.max_leaf_size = 4;  // above the leaf size a split is forced even where it does not pay
  EXPECT_EQ(build_bvh(clusters(0.1f), o).nodes.size(), 3u);
}

TEST(Bvh, BinsCutTheCentroidExtentIntoEqualParts) {
  // Two bins over centroids 0..14: the bin boundary is at 7, so the only split is 4 | 4 (Wald 2007: bins of equal
  // width over the centroid bounds).
  BvhBuildOptions o;
  o.bins = 2;
  o.max_leaf_size = 1;
  const Bvh bvh = build_bvh(box_row(8), o);
  ASSERT_FALSE(bvh.nodes[0].is_leaf());
  EXPECT_EQ(subtree_prims(bvh, bvh.nodes[0].first), 4u);
  EXPECT_EQ(subtree_prims(bvh, bvh.nodes[0].first + 1), 4u);
}

TEST(Bvh, ARowIsCutNearItsMiddleForEveryLeafBlockSize) {
  // A row of 64 separated boxes: the SAH's best first cut is near the middle, whatever the block size the leaf
  // costs are rounded to (the sweep prices leaves of odd block sizes one count at a time).
  for (int block : {1, 2, 3, 4, 5}) {
    BvhBuildOptions o;
    o.leaf_block_size = block;
    o.max_leaf_size = 1;
    const Bvh bvh = build_bvh(box_row(64), o);
    ASSERT_FALSE(bvh.nodes[0].is_leaf());
    const uint32_t left = subtree_prims(bvh, bvh.nodes[0].first);
    EXPECT_GE(left, 24u) << "block " << block;
    EXPECT_LE(left, 40u) << "block " << block;
  }
}

TEST(Bvh, ANonFinitePrimitiveDoesNotSpoilTheTree) {
  // One primitive with a NaN box (a triangle with a NaN vertex) among 5000: it gets an empty box, and the tree over
  // the others is as good as without it. Its centroid must not make the centroid bounds NaN, which leaves the
  // node to the median fallback; the second set of boxes is two clusters of 4000 and 1000, which a median split
  // cuts through.
  const std::vector<AABB> uniform = prim_boxes(uniform_soup(5000, 44));
  const std::vector<AABB> clusters = [&] {
    std::vector<AABB> c = uniform;
    for (size_t i = 0; i < 1000; ++i) c[i] = {c[i].lo + vec3(1000.0f, 0, 0), c[i].hi + vec3(1000.0f, 0, 0)};
    return c;
  }();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const std::vector<AABB>* boxes : {&uniform, &clusters}) {
    const float clean = sah_cost(build_bvh(*boxes, {}), 1.0f);
    for (size_t at : {size_t(0), size_t(2500), boxes->size()}) {
      std::vector<AABB> with = *boxes;
      with.insert(with.begin() + std::ptrdiff_t(at), AABB{vec3(nan, 0.0f, 0.0f), vec3(nan, 1.0f, 1.0f)});
      const Bvh bvh = build_bvh(with, {});
      std::vector<AABB> built = with;  // what the builder makes of the NaN box: an empty one
      built[at] = AABB{};
      check_structure(bvh, built, BvhBuildOptions{}.max_leaf_size);
      EXPECT_LE(sah_cost(bvh, 1.0f), 1.02f * clean) << "NaN box at " << at;
    }
  }
}

TEST(Bvh, RefitAfterMovingGeometryStaysExact) {
  Soup s = mixed_soup(5000, 20, 8);
  TraceGeometry g = make_trace_geometry(s.tris, s.spheres);
  const Soup before = s;
  Pcg32 rng(9, 9);
  for (uint32_t i = 0; i < s.tri_count(); i += 7) {
    if (i % 2) {
      vec3 shift = 3.0f * (rand3(rng) - 0.5f);
      for (int k = 0; k < 3; ++k) s.tris[3 * i + k] += shift;
    } else {
      s.tris[3 * i + rng.next_u32() % 3] += 2.0f * (rand3(rng) - 0.5f);  // deform
    }
  }
  s.tris[0] += vec3(20.0f, 0, 0);  // far outside the old root box
  for (auto& sp : s.spheres) sp.radius *= 1.5f, sp.center.y += 0.5f;
  refit_trace_geometry(g, s.tris, s.spheres);
  check_trace_structure(g, s);
  EXPECT_GE(g.bounds().hi.x, s.tris[0].x);
  // The motion must matter: on a fixed set of rays the old and new scenes give different answers.
  BruteForce old_brute(before), new_brute(s);
  Pcg32 ray_rng(11, 3);
  std::vector<uint8_t> mask;
  int changed = 0;
  const std::vector<AABB> boxes = node_boxes(g);
  for (int i = 0; i < 2000; ++i) {
    Ray ray = make_test_ray(ray_rng, i, s, boxes);
    Hit a, b;
    changed += old_brute.closest(ray, a, mask) != new_brute.closest(ray, b, mask) || a.prim != b.prim || a.t != b.t;
  }
  EXPECT_GT(changed, 100);
  expect_matches_brute_force(g, s, 30000, 10, 20);
}

}  // namespace
}  // namespace pt
