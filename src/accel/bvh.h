#pragma once
/// A bounding volume hierarchy over abstract primitives, after madmann91/bvh: the builder takes a span of boxes
/// and returns flat nodes plus a primitive permutation; traversal is a template over the leaf test, so
/// the hot loop has no virtual call and no std::function.
#include <cstdint>
#include <span>
#include <vector>

#include "core/aabb.h"
#include "core/huge_page_allocator.h"
#include "core/ray.h"

namespace pt {

/// 32 bytes. Interior nodes (count == 0) have children `first` and `first + 1`; leaves own
/// prim_indices[first, first + count).
struct BvhNode {
  AABB bounds;
  uint32_t first = 0;
  uint32_t count = 0;
  bool is_leaf() const { return count != 0; }
};

/// The builder never makes a tree deeper than this (it falls back to median splits), so traversal stacks are fixed.
inline constexpr int kBvhMaxDepth = 96;

struct Bvh {
  HugeVector<BvhNode> nodes;          ///< nodes[0] is the root
  HugeVector<uint32_t> prim_indices;  ///< leaf order -> input primitive index
  int depth = 0;
};

struct BvhBuildOptions {
  int bins = 32;              ///< SAH bins per axis (Wald 2007, "On fast construction of SAH-based BVHs")
  int max_leaf_size = 8;      ///< a leaf is forced to split above this many primitives
  float traversal_cost = 1.0f;  ///< cost of one node visit relative to one primitive test
  /// Leaves are tested in SIMD blocks of this many primitives, so the SAH charges a leaf for whole blocks
  /// (as Embree's builders do for its 4-wide triangle leaves).
  int leaf_block_size = 1;
  int threads = 0;  ///< build threads; 0 = all hardware threads
};

/// What a leaf of `count` primitives costs in the SAH, in primitive tests: whole blocks of leaf_block_size.
inline float sah_leaf_tests(uint32_t count, const BvhBuildOptions& options) {
  const uint32_t block = options.leaf_block_size > 1 ? uint32_t(options.leaf_block_size) : 1u;
  return float((count + block - 1) / block * block);
}

/// Binned SAH build, top-down. `boxes[i]` bounds primitive i; its centroid is the box center (as in Embree and
/// pbrt). Non-finite boxes count as empty (finite_or_empty), with the origin as centroid.
Bvh build_bvh(std::span<const AABB> boxes, const BvhBuildOptions& options = {});
/// The same over triangles (triangle i is vertices 3i..3i+2), without an array of their boxes: on a 6M-triangle mesh
/// that array and its centers were 230 MB of fresh memory, and touching fresh memory is a large part of a build.
Bvh build_triangle_bvh(std::span<const vec3> triangle_vertices, const BvhBuildOptions& options = {});

/// Reference builder: the exact SAH split over every primitive boundary on all three axes (a full sweep,
/// O(n log^2 n)). Slow; it exists to measure how much the binned builder loses. Inputs must be finite.
Bvh build_bvh_sweep(std::span<const AABB> boxes, std::span<const vec3> centers, const BvhBuildOptions& options = {});

/// Expected cost of a random ray under the SAH model (MacDonald and Booth 1990), normalized by the root area:
/// sum over interior nodes of traversal_cost * A(n)/A(root) + sum over leaves of count * A(n)/A(root).
float sah_cost(const Bvh& bvh, float traversal_cost = 1.0f);

/// Per-ray data for the slab test, computed once per ray.
struct RayBoxData {
  vec3 org;
  vec3 inv_dir;
  int dir_neg[3];
};
inline RayBoxData make_ray_box_data(const Ray& ray) {
  RayBoxData r;
  r.org = ray.org;
  for (int i = 0; i < 3; ++i) {
    r.inv_dir[i] = ray.dir[i] != 0.0f ? 1.0f / ray.dir[i] : std::copysign(kInfinity, ray.dir[i]);
    r.dir_neg[i] = r.inv_dir[i] < 0.0f;
  }
  return r;
}

/// Slab test; returns the entry distance or +inf on a miss. Robust: the far distances and tmax are scaled up by
/// 1 + 2 gamma(3) (Ize 2013, "Robust BVH Ray Traversal"), so rounding of the slab distances never culls a box that
/// holds a hit just inside tmax, and NaNs from 0 * inf never tighten the interval.
inline float intersect_box(const AABB& b, const RayBoxData& r, float tmax) {
  constexpr float kRobust = 1.0f + 2.0f * gamma_bound(3);
  float t0 = 0.0f, t1 = tmax * kRobust;
  for (int i = 0; i < 3; ++i) {
    float near = ((r.dir_neg[i] ? b.hi[i] : b.lo[i]) - r.org[i]) * r.inv_dir[i];
    float far = ((r.dir_neg[i] ? b.lo[i] : b.hi[i]) - r.org[i]) * r.inv_dir[i];
    far *= kRobust;
    t0 = near > t0 ? near : t0;
    t1 = far < t1 ? far : t1;
  }
  return t0 <= t1 ? t0 : kInfinity;
}

/// Ordered front-to-back traversal. `leaf(prim_begin, prim_end, ray)` tests the primitives of a leaf (leaf order
/// positions) and returns true if it found a hit, shrinking ray.tmax itself. With kAnyHit the traversal stops at
/// the first hit (shadow rays).
template <bool kAnyHit, class LeafTest>
bool traverse_bvh(const Bvh& bvh, Ray& ray, LeafTest&& leaf) {
  if (bvh.nodes.empty()) return false;
  const RayBoxData rd = make_ray_box_data(ray);
  struct Entry { uint32_t node; float t; };
  Entry stack[kBvhMaxDepth + 2];
  int top = 0;
  bool hit = false;
  if (intersect_box(bvh.nodes[0].bounds, rd, ray.tmax) == kInfinity) return false;
  uint32_t node_index = 0;
  for (;;) {
    const BvhNode& node = bvh.nodes[node_index];
    if (node.is_leaf()) {
      if (leaf(node.first, node.first + node.count, ray)) {
        hit = true;
        if constexpr (kAnyHit) return true;
      }
    } else {
      uint32_t left = node.first, right = node.first + 1;
      float tl = intersect_box(bvh.nodes[left].bounds, rd, ray.tmax);
      float tr = intersect_box(bvh.nodes[right].bounds, rd, ray.tmax);
      if (tl != kInfinity && tr != kInfinity) {
        if (tr < tl) { std::swap(left, right); std::swap(tl, tr); }
        stack[top++] = {right, tr};
        node_index = left;
        continue;
      }
      if (tl != kInfinity) { node_index = left; continue; }
      if (tr != kInfinity) { node_index = right; continue; }
    }
    // Pop the nearest pending node that is still in front of the closest hit found so far.
    for (;;) {
      if (top == 0) return hit;
      Entry e = stack[--top];
      if (e.t <= ray.tmax) { node_index = e.node; break; }
    }
  }
}

}  // namespace pt
