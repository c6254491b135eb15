// Watertightness (Woop, Benthin and Wald 2013): rays from inside a closed mesh aimed exactly at its shared vertices
// and edges never escape, at any scale and far from the world origin; rays at the shared edges of a flat grid always
// hit it. Robust spawning (pbrt-v4 section 6.8.6): a ray leaving a surface point along the side of its normal never
// re-hits the triangle it left, and never hits a convex mesh it leaves outward.
#include <gtest/gtest.h>

#include <map>

#include "accel/geometry.h"
#include "core/rng.h"
#include "core/sampling.h"

namespace pt {
namespace {

struct Mesh {
  std::vector<vec3> verts;
  std::vector<uvec3> tris;
  float inner_radius;  ///< every surface point is at distance in [inner_radius, outer_radius] of the origin
  float outer_radius;
};

/// An icosphere: closed, every edge shared by exactly two triangles, outward (CCW) winding.
Mesh make_icosphere(int subdivisions) {
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  Mesh m;
  m.verts = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
             {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (vec3& v : m.verts) v = glm::normalize(v);
  m.tris = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
            {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
            {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.verts.push_back(glm::normalize(m.verts[a] + m.verts[b]));
      return mid[key] = uint32_t(m.verts.size() - 1);
    };
    std::vector<uvec3> next;
    for (uvec3 f : m.tris) {
      uint32_t a = midpoint(f.x, f.y), b = midpoint(f.y, f.z), c = midpoint(f.z, f.x);
      next.insert(next.end(), {{f.x, a, c}, {f.y, b, a}, {f.z, c, b}, {a, b, c}});
    }
    m.tris = next;
  }
  m.inner_radius = 0.99f;  // the flattest face of a 4-times subdivided icosphere is ~0.9986 from the center
  m.outer_radius = 1.0f;
  return m;
}

/// The cube [-1,1]^3 as 12 triangles, outward winding.
Mesh make_cube() {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.verts.push_back(vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& q : quads) m.tris.insert(m.tris.end(), {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}});
  m.inner_radius = 1.0f;
  m.outer_radius = std::sqrt(3.0f);
  return m;
}

std::vector<std::pair<uint32_t, uint32_t>> unique_edges(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> count;
  for (uvec3 f : m.tris)
    for (int k = 0; k < 3; ++k) count[std::minmax(f[k], f[(k + 1) % 3])]++;
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  for (auto& [e, n] : count) {
    EXPECT_EQ(n, 2) << "the mesh must be closed";
    edges.push_back(e);
  }
  return edges;
}

struct Placement {
  float scale;
  vec3 offset;
};
const Placement kPlacements[] = {{1.0f, vec3(0)}, {1e-3f, vec3(0)}, {1e3f, vec3(0)}, {1.0f, vec3(1e5f, -1e5f, 1e5f)}};

/// World-space triangle soup of the mesh; shared vertices stay bit-identical, so the mesh stays closed.
std::vector<vec3> place(const Mesh& m, const Placement& pl) {
  std::vector<vec3> out;
  for (uvec3 f : m.tris)
    for (int k = 0; k < 3; ++k) out.push_back(m.verts[f[k]] * pl.scale + pl.offset);
  return out;
}

/// Rays from `origins_local` inside the mesh toward every vertex, toward points at parameters 1/2, 1/3 and a random
/// one on every edge, and in random directions. Every ray must hit, at the distance of the target (targeted rays)
/// or between the inner and outer radius (random rays). Returns the number of rays.
int expect_no_escape(const Mesh& m, std::span<const vec3> origins_local, int random_rays, uint64_t seed) {
  const auto edges = unique_edges(m);
  int total = 0;
  for (const Placement& pl : kPlacements) {
    std::vector<vec3> world(m.verts.size());
    for (size_t i = 0; i < world.size(); ++i) world[i] = m.verts[i] * pl.scale + pl.offset;
    TraceGeometry g = make_trace_geometry(place(m, pl), {});
    Pcg32 rng(seed, 2);
    // Rounding of coordinates near the offset moves targets off the surface by ~1 float spacing there.
    const float far = max_component(glm::abs(pl.offset));
    const double tol = 1e-4 * pl.scale + (far > 0.0f ? 4.0 * std::ldexp(1.0, std::ilogb(far) - 23) : 0.0);
    int escaped = 0, wrong_t = 0;
    double worst = 0.0;
    for (vec3 o_local : origins_local) {
      const vec3 o = o_local * pl.scale + pl.offset;
      std::vector<vec3> targets = world;
      for (auto [a, b] : edges)
        for (float t : {0.5f, 1.0f / 3.0f, rng.next_float()}) targets.push_back(world[a] + t * (world[b] - world[a]));
      auto shoot = [&](vec3 dir, double expected_lo, double expected_hi) {
        Ray ray{o, dir, kInfinity};
        Hit hit;
        ++total;
        if (!intersect_closest(g, ray, hit)) {
          if (++escaped <= 3) ADD_FAILURE() << "escaped: dir " << dir.x << "," << dir.y << "," << dir.z;
          return;
        }
        double err = std::max({0.0, expected_lo - hit.t, hit.t - expected_hi});
        worst = std::max(worst, err);
        wrong_t += err > tol;
      };
      for (vec3 target : targets) {
        double dist = glm::length(dvec3(target) - dvec3(o));
        shoot(glm::normalize(target - o), dist, dist);
      }
      for (int i = 0; i < random_rays; ++i) {
        double d_local = glm::length(o_local);
        shoot(sample_uniform_sphere(vec2(rng.next_float(), rng.next_float())),
              (m.inner_radius - d_local) * pl.scale, (m.outer_radius + d_local) * pl.scale);
      }
    }
    EXPECT_EQ(escaped, 0) << "scale " << pl.scale << " offset " << pl.offset.x;
    EXPECT_EQ(wrong_t, 0) << "scale " << pl.scale << " offset " << pl.offset.x << ": worst distance error " << worst
                          << " > " << tol;
  }
  return total;
}

TEST(Watertight, RaysFromInsideAnIcosphereNeverEscape) {
  Mesh m = make_icosphere(4);
  ASSERT_EQ(m.tris.size(), 5120u);
  const vec3 origins[] = {vec3(0), vec3(0.3f, -0.2f, 0.1f)};
  EXPECT_GT(expect_no_escape(m, origins, 3000, 1), 200000);
}

TEST(Watertight, RaysFromInsideACubeNeverEscape) {
  // From the center every vertex ray passes exactly through a corner shared by up to six triangles. (Origins must
  // stay inside after rounding at 1e5, where floats are 2^-7 apart: -0.999 + 1e5 would land on the face.)
  const vec3 origins[] = {vec3(0), vec3(0.5f, -0.7f, 0.2f), vec3(0.9f, 0.9f, -0.9f), vec3(-0.98f, 0.25f, 0.5f)};
  EXPECT_GT(expect_no_escape(make_cube(), origins, 4000, 3), 60000);
}

TEST(Watertight, RaysAtSharedEdgesAndVerticesOfAGridAlwaysHit) {
  // A 64x64 grid of unit quads, each split along its diagonal, in the plane z = 0 (then scaled and offset). Rays
  // from both sides aimed at interior vertices and at points on interior edges (axis edges and diagonals), plus
  // rays along -z through vertices and diagonal midpoints, where edge functions are exactly zero.
  const int n = 64;
  Pcg32 rng(4, 4);
  for (const Placement& pl : kPlacements) {
    auto at = [&](float x, float y) { return vec3(x, y, 0.0f) * pl.scale + pl.offset; };
    std::vector<vec3> tv;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        vec3 p00 = at(float(i), float(j)), p10 = at(float(i + 1), float(j)), p01 = at(float(i), float(j + 1)),
             p11 = at(float(i + 1), float(j + 1));
        tv.insert(tv.end(), {p00, p10, p11, p00, p11, p01});
      }
    TraceGeometry g = make_trace_geometry(tv, {});
    std::vector<vec3> targets;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const bool interior_i = i > 0 && i < n, interior_j = j > 0 && j < n;
        if (interior_i && interior_j) targets.push_back(at(float(i), float(j)));
        for (float t : {0.5f, 1.0f / 3.0f, rng.next_float()}) {
          if (i < n && interior_j) targets.push_back(at(float(i) + t, float(j)));        // along x
          if (j < n && interior_i) targets.push_back(at(float(i), float(j) + t));        // along y
          if (i < n && j < n) targets.push_back(at(float(i) + t, float(j) + t));         // diagonal
        }
      }
    int missed = 0, off_plane = 0, total = 0;
    const float plane_tol = 1e-5f * pl.scale;
    auto shoot = [&](vec3 o, vec3 target) {
      Ray ray{o, glm::normalize(target - o), kInfinity};
      Hit hit;
      ++total;
      if (!intersect_closest(g, ray, hit)) {
        if (++missed <= 3) ADD_FAILURE() << "missed target " << target.x << "," << target.y << "," << target.z;
        return;
      }
      off_plane += std::abs(double(o.z) + double(hit.t) * ray.dir.z - double(pl.offset.z)) > plane_tol;
    };
    for (vec3 target : targets) {
      for (float side : {1.0f, -1.0f}) {
        vec3 lateral(8.0f * rng.next_float() - 4.0f, 8.0f * rng.next_float() - 4.0f, side * (1.0f + 4.0f * rng.next_float()));
        shoot(target + pl.scale * lateral, target);
      }
    }
    for (int i = 1; i < n; ++i)
      for (int j = 1; j < n; ++j)
        for (vec3 target : {at(float(i), float(j)), at(float(i) - 0.5f, float(j) - 0.5f)})
          shoot(target + vec3(0, 0, 3.0f * pl.scale), target);
    EXPECT_EQ(missed, 0) << "of " << total << " at scale " << pl.scale << " offset " << pl.offset.x;
    EXPECT_EQ(off_plane, 0) << "hits off the grid plane at scale " << pl.scale << " offset " << pl.offset.x;
    EXPECT_GT(total, 80000);
  }
}

/// A direction on the side `side` (+1 / -1) of the true plane of (p0, p1, p2): cosine-distributed for even i,
/// grazing (cosine 1e-2 .. 1e-5 to the float normal) for odd i. Returns false if rounding put it on the other side.
bool direction_on_side(Pcg32& rng, int i, vec3 ng, float side, vec3 p0, vec3 p1, vec3 p2, vec3& dir) {
  vec3 local = sample_cosine_hemisphere(vec2(rng.next_float(), rng.next_float()));
  if (i % 2) {
    float c = std::ldexp(1.0f, -7 - int(rng.next_u32() % 11));  // 2^-7 .. 2^-17
    vec2 xy = glm::normalize(vec2(local.x, local.y) + vec2(1e-3f, 0.0f));
    local = vec3(xy * std::sqrt(1.0f - c * c), c);
  }
  vec3 n = side * ng;
  vec3 t = glm::normalize(glm::cross(n, std::abs(n.x) > 0.5f ? vec3(0, 1, 0) : vec3(1, 0, 0)));
  dir = glm::normalize(local.x * t + local.y * glm::cross(n, t) + local.z * n);
  dvec3 n_true = glm::cross(dvec3(p1) - dvec3(p0), dvec3(p2) - dvec3(p0));
  return side * glm::dot(dvec3(dir), n_true) > 0.0;
}

/// A surface point the way render code makes it: p = b0 p0 + b1 p1 + b2 p2 with its rounding bound
/// gamma(7) (|b0 p0| + |b1 p1| + |b2 p2|) and the float geometric normal.
SurfacePoint surface_point(vec3 p0, vec3 p1, vec3 p2, float b1, float b2) {
  float b0 = 1.0f - b1 - b2;
  vec3 p = b0 * p0 + b1 * p1 + b2 * p2;
  vec3 err = gamma_bound(7) * (glm::abs(b0 * p0) + glm::abs(b1 * p1) + glm::abs(b2 * p2));
  return {p, err, glm::normalize(glm::cross(p1 - p0, p2 - p0))};
}

TEST(SpawnRay, LeavingATriangleNeverHitsItAgain) {
  const float scales[] = {1e-4f, 1e-2f, 1.0f, 1e2f, 1e4f};
  const float translations[] = {0.0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f};
  Pcg32 rng(7, 7);
  float largest_ok = -1.0f;
  bool all_ok_so_far = true;
  for (float offset : translations) {
    int rehits_here = 0;
    for (float scale : scales) {
      int rehits = 0, tested = 0;
      for (int i = 0; i < 4000; ++i) {
        vec3 base = offset * vec3(rng.next_u32() % 2 ? 1 : -1, rng.next_u32() % 2 ? 1 : -1, rng.next_u32() % 2 ? 1 : -1);
        vec3 p0 = base + scale * vec3(rng.next_float(), rng.next_float(), rng.next_float());
        vec3 p1 = base + scale * vec3(rng.next_float(), rng.next_float(), rng.next_float());
        vec3 p2 = base + scale * vec3(rng.next_float(), rng.next_float(), rng.next_float());
        if (!(glm::length(glm::cross(p1 - p0, p2 - p0)) > 1e-3f * scale * scale)) continue;
        // Half the points from sampled barycentrics, half from where a ray actually hit (as the renderer does).
        float b1, b2;
        if (i % 4 < 2) {
          vec3 b = sample_uniform_triangle(vec2(rng.next_float(), rng.next_float()));
          b1 = b.y, b2 = b.z;
        } else {
          vec3 b = sample_uniform_triangle(vec2(rng.next_float(), rng.next_float()));
          vec3 target = b.x * p0 + b.y * p1 + b.z * p2;
          vec3 from = target + scale * sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
          TriangleHit th;
          Ray cam{from, glm::normalize(target - from), kInfinity};
          if (!intersect_triangle(make_watertight_ray(cam), kInfinity, p0, p1, p2, th)) continue;
          b1 = th.b1, b2 = th.b2;
        }
        SurfacePoint sp = surface_point(p0, p1, p2, b1, b2);
        vec3 dir;
        if (!direction_on_side(rng, i, sp.ng, i % 8 < 4 ? 1.0f : -1.0f, p0, p1, p2, dir)) continue;
        ++tested;
        Ray ray = spawn_ray(sp, dir);
        TriangleHit th;
        if (intersect_triangle(make_watertight_ray(ray), kInfinity, p0, p1, p2, th)) ++rehits;
      }
      EXPECT_EQ(rehits, 0) << "scale " << scale << " translation " << offset << ": " << rehits << " of " << tested;
      if (scale >= 1e-7f * offset) {  // else the triangles are a few float spacings across and mostly degenerate
        EXPECT_GT(tested, 1000) << "scale " << scale << " translation " << offset;
      }
      rehits_here += rehits;
    }
    all_ok_so_far = all_ok_so_far && rehits_here == 0;
    if (all_ok_so_far) largest_ok = offset;
  }
  RecordProperty("largest_translation_without_rehits", std::to_string(largest_ok));
  EXPECT_EQ(largest_ok, 1e5f) << "spawning holds only up to translation " << largest_ok;
}

TEST(SpawnRay, LeavingAConvexMeshOutwardHitsNothingInwardHitsTheFarSide) {
  // Outward rays from any point of a convex closed mesh stay outside every face plane, so they hit nothing at all
  // (neighbours included); inward rays never hit the face they left, and hit another face unless they graze
  // (cosine < 2^-7): leaving next to a shared edge, a grazing ray crosses the neighbour face within the rounding
  // distance the triangle test treats as t = 0, which is accepted (counted, bounded) rather than asserted away.
  Mesh m = make_icosphere(3);
  Pcg32 rng(8, 8);
  for (const Placement& pl : kPlacements) {
    std::vector<vec3> tv = place(m, pl);
    TraceGeometry g = make_trace_geometry(tv, {});
    int outward_hits = 0, inward_wrong = 0, grazing_escapes = 0, tested = 0;
    for (int i = 0; i < 20000; ++i) {
      uint32_t f = rng.next_u32() % uint32_t(m.tris.size());
      vec3 p0 = tv[3 * f], p1 = tv[3 * f + 1], p2 = tv[3 * f + 2];
      vec3 b = sample_uniform_triangle(vec2(rng.next_float(), rng.next_float()));
      SurfacePoint sp = surface_point(p0, p1, p2, b.y, b.z);
      const float side = i % 2 ? 1.0f : -1.0f;  // the winding is outward
      vec3 dir;
      if (!direction_on_side(rng, i / 2, sp.ng, side, p0, p1, p2, dir)) continue;
      ++tested;
      Ray ray = spawn_ray(sp, dir);
      if (side > 0.0f) {
        outward_hits += intersect_any(g, ray);
      } else {
        Hit hit;
        const bool h = intersect_closest(g, ray, hit);
        inward_wrong += h ? hit.prim == f : glm::dot(dir, sp.ng) < -0x1p-7f;
        grazing_escapes += !h;
      }
    }
    EXPECT_EQ(outward_hits, 0) << "scale " << pl.scale << " offset " << pl.offset.x;
    EXPECT_EQ(inward_wrong, 0) << "scale " << pl.scale << " offset " << pl.offset.x;
    EXPECT_LE(grazing_escapes, 5) << "scale " << pl.scale << " offset " << pl.offset.x;
    EXPECT_GT(tested, 15000);
  }
}

}  // namespace
}  // namespace pt
