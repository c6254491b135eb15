/// Full-sweep SAH build (MacDonald and Booth 1990; Wald 2007 section 3): every node tries every split between
/// consecutive centroids on all three axes. It is the quality reference the binned builder is measured against
/// (tests and bench/raycast), not something the renderer runs.
#include <algorithm>
#include <numeric>

#include "accel/bvh.h"

namespace pt {
namespace {

struct SweepBuilder {
  std::span<const AABB> boxes;
  std::span<const vec3> centers;
  const BvhBuildOptions& options;
  Bvh& bvh;
  std::vector<float> right_area;

  float blocks(uint32_t n) const { return sah_leaf_tests(n, options); }

  void build(uint32_t node, uint32_t begin, uint32_t end, int depth) {
    bvh.depth = std::max(bvh.depth, depth);
    uint32_t* prims = bvh.prim_indices.data();
    const uint32_t count = end - begin;
    AABB bounds;
    for (uint32_t i = begin; i < end; ++i) bounds.extend(boxes[prims[i]]);
    bvh.nodes[node].bounds = bounds;
    auto leaf = [&] {
      bvh.nodes[node].first = begin;
      bvh.nodes[node].count = count;
    };
    if (count == 1) return leaf();
    int best_axis = -1;
    uint32_t best_mid = 0;
    float best_cost = kInfinity;
    for (int a = 0; a < 3; ++a) {
      auto by_axis = [&](uint32_t x, uint32_t y) {
        return centers[x][a] < centers[y][a] || (centers[x][a] == centers[y][a] && x < y);
      };
      std::sort(prims + begin, prims + end, by_axis);
      AABB acc;
      for (uint32_t i = end - 1; i > begin; --i) {
        acc.extend(boxes[prims[i]]);
        right_area[i] = acc.half_area();
      }
      acc = AABB{};
      for (uint32_t i = begin; i + 1 < end; ++i) {
        acc.extend(boxes[prims[i]]);
        const uint32_t n_left = i + 1 - begin;
        float cost = acc.half_area() * blocks(n_left) + right_area[i + 1] * blocks(count - n_left);
        if (cost < best_cost) best_cost = cost, best_axis = a, best_mid = i + 1;
      }
    }
    const float area = bounds.half_area();
    if (count <= uint32_t(std::max(1, options.max_leaf_size)) &&
        area * blocks(count) <= options.traversal_cost * area + best_cost)
      return leaf();
    if (depth >= kBvhMaxDepth - 32) best_mid = begin + count / 2;  // bounded depth, as in the binned builder
    if (best_axis != 2) {
      std::sort(prims + begin, prims + end, [&](uint32_t x, uint32_t y) {
        return centers[x][best_axis] < centers[y][best_axis] ||
               (centers[x][best_axis] == centers[y][best_axis] && x < y);
      });
    }
    const uint32_t left = uint32_t(bvh.nodes.size());
    bvh.nodes[node].first = left;
    bvh.nodes[node].count = 0;
    bvh.nodes.resize(bvh.nodes.size() + 2);
    build(left, begin, best_mid, depth + 1);
    build(left + 1, best_mid, end, depth + 1);
  }
};

}  // namespace

Bvh build_bvh_sweep(std::span<const AABB> boxes, std::span<const vec3> centers, const BvhBuildOptions& options) {
  Bvh bvh;
  const uint32_t n = uint32_t(boxes.size());
  if (n == 0) return bvh;
  bvh.prim_indices.resize(n);
  std::iota(bvh.prim_indices.begin(), bvh.prim_indices.end(), 0u);
  bvh.nodes.reserve(2 * size_t(n));
  bvh.nodes.resize(1);
  SweepBuilder b{boxes, centers, options, bvh, std::vector<float>(n + 1)};
  b.build(0, 0, n, 0);
  return bvh;
}

}  // namespace pt
