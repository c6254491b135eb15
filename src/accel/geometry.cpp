#include "accel/geometry.h"

#include <chrono>

#include "accel/sphere.h"

namespace pt {

namespace {

void fill_packed(TraceGeometry& g, std::span<const vec3> triangle_vertices, std::span<const TraceSphere> spheres) {
  g.packed.resize(g.bvh.prim_indices.size());
  for (size_t k = 0; k < g.packed.size(); ++k) {
    uint32_t id = g.bvh.prim_indices[k];
    TraceGeometry::Packed& p = g.packed[k];
    p.prim = id;
    if (id < g.triangle_count) {
      p.p0 = triangle_vertices[3 * id];
      p.p1 = triangle_vertices[3 * id + 1];
      p.p2 = triangle_vertices[3 * id + 2];
    } else {
      const TraceSphere& s = spheres[id - g.triangle_count];
      p.p0 = s.center;
      p.p1 = vec3(s.radius, 0, 0);
      p.p2 = vec3(0.0f);
    }
  }
}

AABB packed_bounds(const TraceGeometry& g, const TraceGeometry::Packed& p) {
  AABB b;
  if (p.prim < g.triangle_count) {
    b.extend(p.p0);
    b.extend(p.p1);
    b.extend(p.p2);
  } else {
    b = {p.p0 - vec3(p.p1.x), p.p0 + vec3(p.p1.x)};
  }
  return b;
}

template <bool kAnyHit>
bool trace(const TraceGeometry& g, Ray& ray, Hit* hit) {
  const WatertightRay wray = make_watertight_ray(ray);
  const uint32_t tri_count = g.triangle_count;
  return traverse_bvh<kAnyHit>(g.bvh, ray, [&](uint32_t begin, uint32_t end, Ray& r) {
    bool found = false;
    for (uint32_t k = begin; k < end; ++k) {
      const TraceGeometry::Packed& p = g.packed[k];
      if (p.prim < tri_count) {
        TriangleHit th;
        if (intersect_triangle(wray, r.tmax, p.p0, p.p1, p.p2, th)) {
          if constexpr (kAnyHit) return true;
          r.tmax = th.t;
          *hit = {th.t, p.prim, th.b1, th.b2};
          found = true;
        }
      } else {
        float t = intersect_sphere(r, p.p0, p.p1.x, r.tmax);
        if (t < r.tmax) {
          if constexpr (kAnyHit) return true;
          r.tmax = t;
          *hit = {t, p.prim, 0.0f, 0.0f};
          found = true;
        }
      }
    }
    return found;
  });
}

}  // namespace

TraceGeometry make_trace_geometry(std::span<const vec3> triangle_vertices, std::span<const TraceSphere> spheres,
                                  const BvhBuildOptions& options) {
  auto start = std::chrono::steady_clock::now();
  TraceGeometry g;
  g.triangle_count = uint32_t(triangle_vertices.size() / 3);
  const size_t n = g.triangle_count + spheres.size();
  std::vector<AABB> boxes(n);
  std::vector<vec3> centers(n);
  for (uint32_t i = 0; i < g.triangle_count; ++i) {
    AABB b;
    for (int k = 0; k < 3; ++k) b.extend(triangle_vertices[3 * i + k]);
    boxes[i] = b;
    centers[i] = b.center();
  }
  for (size_t i = 0; i < spheres.size(); ++i) {
    vec3 r(spheres[i].radius);
    boxes[g.triangle_count + i] = {spheres[i].center - r, spheres[i].center + r};
    centers[g.triangle_count + i] = spheres[i].center;
  }
  g.bvh = build_bvh(boxes, centers, options);
  fill_packed(g, triangle_vertices, spheres);
  g.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return g;
}

void refit_trace_geometry(TraceGeometry& g, std::span<const vec3> triangle_vertices,
                          std::span<const TraceSphere> spheres) {
  fill_packed(g, triangle_vertices, spheres);
  // Children always come after their parent in `nodes`, so a reverse sweep sees children first.
  for (size_t i = g.bvh.nodes.size(); i-- > 0;) {
    BvhNode& node = g.bvh.nodes[i];
    AABB b;
    if (node.is_leaf()) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k) b.extend(packed_bounds(g, g.packed[k]));
    } else {
      b = merge(g.bvh.nodes[node.first].bounds, g.bvh.nodes[node.first + 1].bounds);
    }
    node.bounds = b;
  }
}

bool intersect_closest(const TraceGeometry& geometry, Ray& ray, Hit& hit) { return trace<false>(geometry, ray, &hit); }

bool intersect_any(const TraceGeometry& geometry, const Ray& ray) {
  Ray r = ray;
  return trace<true>(geometry, r, nullptr);
}

}  // namespace pt
