#pragma once
/// The traceable geometry of a scene: triangles and spheres behind one BVH. Primitive ids: [0, triangle_count) are
/// triangles in input order, then spheres. Primitive data is stored in BVH leaf order so a leaf reads contiguous
/// memory.
#include <cstdint>
#include <span>
#include <vector>

#include "accel/bvh.h"
#include "accel/triangle.h"

namespace pt {

/// What a closest-hit query returns; the surface details are computed from it afterwards, once per path vertex.
struct Hit {
  float t = kInfinity;
  uint32_t prim = 0;  ///< primitive id (see TraceGeometry)
  float b1 = 0, b2 = 0;  ///< barycentrics of vertices 1 and 2 for triangles
};

struct TraceSphere {
  vec3 center;
  float radius;
};

struct TraceGeometry {
  struct Packed {  ///< a triangle (p0, p1, p2) or a sphere (p0 = center, p1.x = radius), in leaf order
    vec3 p0, p1, p2;
    uint32_t prim;
  };
  uint32_t triangle_count = 0;
  Bvh bvh;
  std::vector<Packed> packed;
  double build_ms = 0.0;

  size_t primitive_count() const { return packed.size(); }
  AABB bounds() const { return bvh.nodes.empty() ? AABB{} : bvh.nodes[0].bounds; }
};

/// Builds the BVH over `triangles` (vertex triples) and `spheres`. Degenerate input is allowed (it just never hits).
TraceGeometry make_trace_geometry(std::span<const vec3> triangle_vertices, std::span<const TraceSphere> spheres,
                                  const BvhBuildOptions& options = {});

/// Updates primitive data and node bounds after vertices or spheres moved, keeping the tree topology (a refit:
/// O(n), no rebuild). Used for interactive edits such as resizing a light; quality degrades only if things move far.
void refit_trace_geometry(TraceGeometry& geometry, std::span<const vec3> triangle_vertices,
                          std::span<const TraceSphere> spheres);

/// Closest hit in (0, ray.tmax); on a hit shrinks ray.tmax to it and fills `hit`.
bool intersect_closest(const TraceGeometry& geometry, Ray& ray, Hit& hit);
/// Any hit in (0, ray.tmax): true if the segment is blocked.
bool intersect_any(const TraceGeometry& geometry, const Ray& ray);

}  // namespace pt
