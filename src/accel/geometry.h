#pragma once
/// The traceable geometry of a scene: triangles behind an 8-wide SIMD BVH, spheres behind a small binary BVH.
/// Primitive ids: [0, triangle_count) are triangles in input order, then spheres.
#include <cstdint>
#include <span>
#include <vector>

#include "accel/bvh.h"
#include "accel/bvh8.h"
#include "accel/triangle.h"
#include "core/sphere.h"

namespace pt {

/// What a closest-hit query returns; the surface details are computed from it afterwards, once per path vertex.
struct Hit {
  float t = kInfinity;
  uint32_t prim = 0;  ///< primitive id (see TraceGeometry)
  float b1 = 0, b2 = 0;  ///< barycentrics of vertices 1 and 2 for triangles
  /// A hit triangle's vertices where the traversal just read them, in cache: its lane of the BVH leaf block,
  /// &Tri4::v[0][0][lane], read with lane_vertex (bvh8.h). The same floats as the vertex array the tree was built
  /// or refitted from. Null for spheres.
  const float* vertices = nullptr;
};

/// Figures about the acceleration structure, for stats output and benchmarks.
struct TraceStats {
  size_t binary_nodes = 0;  ///< nodes of the binary SAH tree the wide tree was collapsed from
  int depth = 0;            ///< depth of the binary tree
  float sah_cost = 0.0f;    ///< sah_cost() of the binary triangle tree
  size_t memory_bytes = 0;  ///< nodes + leaf data of both trees (what traversal reads)
  double build_ms = 0.0;    ///< wall time of make_trace_geometry
};

struct TraceGeometry {
  struct Sphere : SphereShape {  ///< in sphere-BVH leaf order
    uint32_t prim = 0;
  };
  uint32_t triangle_count = 0;
  Bvh8 triangles;               ///< wide BVH over the triangles
  Bvh sphere_bvh;               ///< binary BVH over the spheres (few: scalar traversal is fine)
  std::vector<Sphere> spheres;  ///< sphere_bvh leaf order
  AABB bounds_all;
  TraceStats stats;

  size_t primitive_count() const { return triangle_count + spheres.size(); }
  AABB bounds() const { return bounds_all; }
};

/// The options the triangle tree is built with: `options` with 4-triangle SIMD leaf blocks in the SAH and at most
/// kMaxLeafBlocks blocks per leaf. Exposed so that benchmarks compare a reference build with the same options.
BvhBuildOptions triangle_build_options(const BvhBuildOptions& options);

/// Builds the BVHs over `triangle_vertices` (vertex triples) and `spheres`. Degenerate input is allowed (it just
/// never hits). The triangle build runs on up to `options.threads` threads.
TraceGeometry make_trace_geometry(std::span<const vec3> triangle_vertices, std::span<const SphereShape> spheres,
                                  const BvhBuildOptions& options = {});

/// Updates primitive data and node bounds after vertices or spheres moved, keeping the tree topology (a refit:
/// O(n), no rebuild). Used for interactive edits such as resizing a light; quality degrades only if things move far.
void refit_trace_geometry(TraceGeometry& geometry, std::span<const vec3> triangle_vertices,
                          std::span<const SphereShape> spheres);

/// Closest hit in (0, ray.tmax); on a hit shrinks ray.tmax to it and fills `hit`.
bool intersect_closest(const TraceGeometry& geometry, Ray& ray, Hit& hit);
/// Any hit in (0, ray.tmax): true if the segment is blocked.
bool intersect_any(const TraceGeometry& geometry, const Ray& ray);

}  // namespace pt
