#include "accel/geometry.h"

#include <algorithm>
#include <chrono>

#include "accel/parallel.h"
#include "accel/sphere.h"

namespace pt {

namespace {

void fill_spheres(TraceGeometry& g, std::span<const SphereShape> spheres) {
  g.spheres.resize(g.sphere_bvh.prim_indices.size());
  for (size_t k = 0; k < g.spheres.size(); ++k) {
    const uint32_t i = g.sphere_bvh.prim_indices[k];
    g.spheres[k] = {{spheres[i].center, spheres[i].radius}, g.triangle_count + i};
  }
}

void update_bounds(TraceGeometry& g) {
  g.bounds_all = bvh8_bounds(g.triangles);
  if (!g.sphere_bvh.nodes.empty()) g.bounds_all.extend(g.sphere_bvh.nodes[0].bounds);
}

/// Up to this many spheres are tested one after the other, without their BVH: for a few spheres the tree's ray
/// setup (three divisions) and box tests cost more than the sphere tests they skip (intersect_sphere returns most
/// misses before its first division). The tree is still built: it gives the bounds and serves refits.
constexpr size_t kFlatSpheres = 8;

template <bool kAnyHit>
bool trace_spheres(const TraceGeometry& g, Ray& ray, Hit* hit) {
  auto test = [&](uint32_t begin, uint32_t end, Ray& r) {
    bool found = false;
    for (uint32_t k = begin; k < end; ++k) {
      const TraceGeometry::Sphere& s = g.spheres[k];
      const float t = intersect_sphere(r, s.center, s.radius, r.tmax);
      if (t < r.tmax) {
        if constexpr (kAnyHit) return true;
        r.tmax = t;
        *hit = {t, s.prim, 0.0f, 0.0f};
        found = true;
      }
    }
    return found;
  };
  if (g.spheres.size() <= kFlatSpheres) return test(0, uint32_t(g.spheres.size()), ray);
  return traverse_bvh<kAnyHit>(g.sphere_bvh, ray, test);
}

}  // namespace

BvhBuildOptions triangle_build_options(const BvhBuildOptions& options) {
  BvhBuildOptions o = options;
  o.leaf_block_size = 4;
  o.max_leaf_size = std::clamp(options.max_leaf_size, 1, 4 * int(kMaxLeafBlocks));
  return o;
}

TraceGeometry make_trace_geometry(std::span<const vec3> triangle_vertices, std::span<const SphereShape> spheres,
                                  const BvhBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  TraceGeometry g;
  g.triangle_count = uint32_t(triangle_vertices.size() / 3);
  const int threads = build_threads(options.threads);
  {
    const Bvh binary = build_triangle_bvh(triangle_vertices, triangle_build_options(options));
    g.stats.binary_nodes = binary.nodes.size();
    g.stats.depth = binary.depth;
    g.stats.sah_cost = sah_cost(binary, options.traversal_cost);
    g.triangles = make_bvh8(binary, triangle_vertices, threads);
  }
  {
    std::vector<AABB> boxes(spheres.size());
    for (size_t i = 0; i < spheres.size(); ++i) boxes[i] = spheres[i].bounds();
    // The sphere test runs in double precision, far costlier than a box: one sphere per leaf.
    BvhBuildOptions sphere_options = options;
    sphere_options.threads = 1;
    sphere_options.max_leaf_size = 1;
    g.sphere_bvh = build_bvh(boxes, sphere_options);
    fill_spheres(g, spheres);
  }
  update_bounds(g);
  g.stats.memory_bytes = g.triangles.bytes() +
                         g.sphere_bvh.nodes.size() * sizeof(BvhNode) + g.spheres.size() * sizeof(TraceGeometry::Sphere);
  g.stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return g;
}

void refit_trace_geometry(TraceGeometry& g, std::span<const vec3> triangle_vertices,
                          std::span<const SphereShape> spheres) {
  refit_bvh8(g.triangles, triangle_vertices);
  fill_spheres(g, spheres);
  // Children always come after their parent in `nodes`, so a reverse sweep sees children first.
  for (size_t i = g.sphere_bvh.nodes.size(); i-- > 0;) {
    BvhNode& node = g.sphere_bvh.nodes[i];
    AABB b;
    if (node.is_leaf()) {
      for (uint32_t k = node.first; k < node.first + node.count; ++k)
        b.extend(finite_or_empty(g.spheres[k].bounds()));
    } else {
      b = merge(g.sphere_bvh.nodes[node.first].bounds, g.sphere_bvh.nodes[node.first + 1].bounds);
    }
    node.bounds = b;
  }
  update_bounds(g);
}

bool intersect_closest(const TraceGeometry& g, Ray& ray, Hit& hit) {
  bool found = false;
  if (!g.triangles.empty()) {
    uint32_t prim;
    float b1, b2;
    const float* vertices;
    if (intersect_bvh8(g.triangles, ray, prim, b1, b2, &vertices)) {
      hit = {ray.tmax, prim, b1, b2, vertices};
      found = true;
    }
  }
  if (!g.spheres.empty()) found |= trace_spheres<false>(g, ray, &hit);
  return found;
}

bool intersect_any(const TraceGeometry& g, const Ray& ray) {
  if (!g.triangles.empty() && occluded_bvh8(g.triangles, ray)) return true;
  if (g.spheres.empty()) return false;
  Ray r = ray;
  return trace_spheres<true>(g, r, nullptr);
}

}  // namespace pt
