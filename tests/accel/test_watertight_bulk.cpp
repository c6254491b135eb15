// Watertightness in bulk: 1.25 10^7 rays from inside closed meshes, each aimed exactly at a shared edge or vertex,
// over scales 1e-3..1e3 and offsets of 1e5 and 1e6: not a single ray may escape (Woop et al. 2013 is watertight by
// design).
#include <gtest/gtest.h>

#include <map>

#include "accel/geometry.h"
#include "core/rng.h"

namespace pt {
namespace {

/// Subdivided octahedron projected to the unit sphere: closed, every edge shared by two triangles.
void make_sphere_mesh(int levels, std::vector<vec3>& v, std::vector<uvec3>& t) {
  v = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  t = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto m = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = uint32_t(v.size() - 1);
    };
    std::vector<uvec3> next;
    for (uvec3 f : t) {
      uint32_t a = m(f.x, f.y), b = m(f.y, f.z), c = m(f.z, f.x);
      next.insert(next.end(), {{f.x, a, c}, {f.y, b, a}, {f.z, c, b}, {a, b, c}});
    }
    t.swap(next);
  }
}

TEST(WatertightBulk, TenMillionRaysAtSharedEdgesAndVerticesNeverEscape) {
  std::vector<vec3> verts;
  std::vector<uvec3> tris;
  make_sphere_mesh(5, verts, tris);  // 8192 triangles
  struct Config {
    float scale;
    vec3 offset;
  };
  // At 1e6 the float soup snaps to a 1/16 grid and folds, but stays closed: still no ray may escape.
  const Config configs[] = {{1.0f, vec3(0.0f)},
                            {1e-3f, vec3(0.0f)},
                            {1e3f, vec3(0.0f)},
                            {1.0f, vec3(1e5f, -1e5f, 1e5f)},
                            {1.0f, vec3(1e6f, -1e6f, 1e6f)}};
  const int rays_per_config = 2500000;
  long long total = 0, escaped = 0;
  for (const Config& c : configs) {
    std::vector<vec3> soup;
    for (uvec3 f : tris)
      for (int k = 0; k < 3; ++k) soup.push_back(verts[f[k]] * c.scale + c.offset);
    TraceGeometry g = make_trace_geometry(soup, {});
    Pcg32 rng(uint64_t(c.scale * 1000), 7);
    for (int i = 0; i < rays_per_config; ++i) {
      size_t f = rng.next_u32() % tris.size();
      vec3 a = soup[3 * f], b = soup[3 * f + (1 + i % 2)];
      // Half the rays at vertices, half at points on shared edges.
      vec3 target = (i % 4 == 0) ? a : a + rng.next_float() * (b - a);
      vec3 o = c.offset + c.scale * 0.6f * vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f);
      vec3 d = target - o;
      float len = glm::length(d);
      if (!(len > 0.0f)) continue;
      Ray ray{o, d / len, kInfinity};
      Hit hit;
      ++total;
      if (!intersect_closest(g, ray, hit)) ++escaped;
    }
  }
  EXPECT_EQ(escaped, 0) << "of " << total;
  EXPECT_GE(total, 9900000);
}

}  // namespace
}  // namespace pt
