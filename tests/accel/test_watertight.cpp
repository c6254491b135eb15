// Watertightness (Woop et al. 2013): rays from inside a closed mesh, aimed at its shared edges and vertices,
// never escape, at any scale and far from the origin; robust spawning never re-hits the surface it leaves.
#include <gtest/gtest.h>

#include <map>

#include "accel/geometry.h"
#include "core/rng.h"
#include "core/sampling.h"

namespace pt {
namespace {

/// An icosphere: closed, all edges shared by two triangles.
void make_icosphere(int subdivisions, std::vector<vec3>& verts, std::vector<uvec3>& tris) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  verts = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (vec3& v : verts) v = glm::normalize(v);
  tris = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
          {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      verts.push_back(glm::normalize(verts[a] + verts[b]));
      return mid[key] = uint32_t(verts.size() - 1);
    };
    std::vector<uvec3> next;
    for (uvec3 f : tris) {
      uint32_t a = midpoint(f.x, f.y), b = midpoint(f.y, f.z), c = midpoint(f.z, f.x);
      next.insert(next.end(), {{f.x, a, c}, {f.y, b, a}, {f.z, c, b}, {a, b, c}});
    }
    tris = next;
  }
}

std::vector<vec3> soup(const std::vector<vec3>& v, const std::vector<uvec3>& t, float scale, vec3 offset) {
  std::vector<vec3> out;
  for (uvec3 f : t)
    for (int k = 0; k < 3; ++k) out.push_back(v[f[k]] * scale + offset);
  return out;
}

TEST(Watertight, RaysFromInsideAtEdgesAndVerticesNeverEscape) {
  std::vector<vec3> verts;
  std::vector<uvec3> tris;
  make_icosphere(4, verts, tris);
  struct Case { float scale; vec3 offset; };
  for (Case c : {Case{1.0f, vec3(0)}, Case{1e-3f, vec3(0)}, Case{1e3f, vec3(0)}, Case{1.0f, vec3(1e5f, -1e5f, 1e5f)}}) {
    std::vector<vec3> tv = soup(verts, tris, c.scale, c.offset);
    TraceGeometry g = make_trace_geometry(tv, {});
    Pcg32 rng(1, 2);
    int escaped = 0, total = 0;
    const vec3 origins[] = {vec3(0), vec3(0.3f, -0.2f, 0.1f), vec3(-0.5f, 0.4f, 0.2f)};
    for (vec3 o_local : origins) {
      vec3 o = o_local * c.scale + c.offset;
      for (size_t f = 0; f < tris.size(); ++f) {
        vec3 a = tv[3 * f], b = tv[3 * f + 1], d = tv[3 * f + 2];
        // At vertex a, along edge ab at 1/2, 1/3 and a random point.
        for (vec3 target : {a, 0.5f * (a + b), a + (b - a) / 3.0f, a + rng.next_float() * (d - a)}) {
          Ray ray{o, glm::normalize(target - o), kInfinity};
          Hit hit;
          ++total;
          if (!intersect_closest(g, ray, hit)) ++escaped;
        }
      }
    }
    EXPECT_EQ(escaped, 0) << "of " << total << " at scale " << c.scale << " offset " << c.offset.x;
    EXPECT_GT(total, 60000);
  }
}

TEST(Watertight, GridRaysAtSharedEdgesAndVerticesAlwaysHit) {
  // A 64x64 grid of quads (two triangles each) in z = 0; rays from above aimed exactly at grid lines and corners.
  std::vector<vec3> tv;
  const int n = 64;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      vec3 p00(float(i), float(j), 0), p10(float(i + 1), float(j), 0), p01(float(i), float(j + 1), 0),
          p11(float(i + 1), float(j + 1), 0);
      tv.insert(tv.end(), {p00, p10, p11, p00, p11, p01});
    }
  TraceGeometry g = make_trace_geometry(tv, {});
  Pcg32 rng(4, 4);
  int missed = 0, total = 0;
  for (int i = 1; i < n; ++i)
    for (int j = 1; j < n; ++j)
      for (vec3 target : {vec3(float(i), float(j), 0), vec3(i + 0.5f, float(j), 0), vec3(float(i), j + 0.5f, 0),
                          vec3(i + 0.5f, j + 0.5f, 0)}) {
        vec3 o = target + vec3(rng.next_float() * 8 - 4, rng.next_float() * 8 - 4, 3.0f + rng.next_float());
        Ray ray{o, glm::normalize(target - o), kInfinity};
        Hit hit;
        ++total;
        if (!intersect_closest(g, ray, hit)) ++missed;
      }
  EXPECT_EQ(missed, 0) << "of " << total;
}

TEST(SpawnRay, LeavingASurfaceNeverHitsItAgain) {
  Pcg32 rng(7, 7);
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    for (float offset : {0.0f, 1e3f, 1e5f}) {
      int rehits = 0;
      for (int i = 0; i < 3000; ++i) {
        vec3 base(offset, -offset, offset);
        vec3 p0 = base + scale * vec3(rng.next_float(), rng.next_float(), rng.next_float());
        vec3 p1 = base + scale * vec3(rng.next_float(), rng.next_float(), rng.next_float());
        vec3 p2 = base + scale * vec3(rng.next_float(), rng.next_float(), rng.next_float());
        vec3 ng = glm::cross(p1 - p0, p2 - p0);
        if (!(glm::length(ng) > 0.0f)) continue;
        ng = glm::normalize(ng);
        vec3 b = sample_uniform_triangle(vec2(rng.next_float(), rng.next_float()));
        vec3 p = b.x * p0 + b.y * p1 + b.z * p2;
        vec3 err = gamma_bound(7) * (glm::abs(b.x * p0) + glm::abs(b.y * p1) + glm::abs(b.z * p2));
        vec3 local = sample_cosine_hemisphere(vec2(rng.next_float(), rng.next_float()));
        local.z = std::max(local.z, 1e-4f);  // down to grazing
        vec3 side = i % 2 ? ng : -ng;
        vec3 t = glm::normalize(glm::cross(side, std::abs(side.x) > 0.5f ? vec3(0, 1, 0) : vec3(1, 0, 0)));
        vec3 dir = glm::normalize(local.x * t + local.y * glm::cross(side, t) + local.z * side);
        Ray ray = spawn_ray(SurfacePoint{p, err, ng}, dir);
        TriangleHit th;
        if (intersect_triangle(make_watertight_ray(ray), kInfinity, p0, p1, p2, th)) ++rehits;
      }
      EXPECT_EQ(rehits, 0) << "scale " << scale << " offset " << offset;
    }
  }
}

}  // namespace
}  // namespace pt
