/// Binned SAH BVH construction (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies";
/// pbrt-v4 section 7.3.2).
#include <algorithm>
#include <array>
#include <numeric>

#include "accel/bvh.h"

namespace pt {
namespace {

struct Task {
  uint32_t node, begin, end;
  int depth;
};

struct Bin {
  AABB box;
  uint32_t count = 0;
};

constexpr int kMaxBins = 64;
/// Below this depth the SAH decides; beyond it splits are median splits so the depth stays bounded.
constexpr int kSahDepthLimit = kBvhMaxDepth - 32;

struct Split {
  int axis = -1;
  int bin = 0;  ///< primitives in bins [0, bin] go left
  float cost = kInfinity;
};

Split find_binned_split(std::span<const AABB> boxes, std::span<const vec3> centers, std::span<const uint32_t> prims,
                        const AABB& centroid_bounds, int bin_count) {
  Split best;
  vec3 extent = centroid_bounds.extent();
  for (int axis = 0; axis < 3; ++axis) {
    if (!(extent[axis] > 0.0f)) continue;
    std::array<Bin, kMaxBins> bins{};
    float scale = float(bin_count) / extent[axis];
    for (uint32_t p : prims) {
      int b = std::min(bin_count - 1, int((centers[p][axis] - centroid_bounds.lo[axis]) * scale));
      b = std::max(b, 0);
      bins[b].box.extend(boxes[p]);
      bins[b].count++;
    }
    // Sweep from the right to get the cost of every right side, then from the left.
    std::array<float, kMaxBins> right_cost{};
    AABB acc;
    uint32_t count = 0;
    for (int b = bin_count - 1; b > 0; --b) {
      acc.extend(bins[b].box);
      count += bins[b].count;
      right_cost[b - 1] = acc.half_area() * float(count);
    }
    acc = AABB{};
    count = 0;
    for (int b = 0; b < bin_count - 1; ++b) {
      acc.extend(bins[b].box);
      count += bins[b].count;
      float cost = acc.half_area() * float(count) + right_cost[b];
      if (count > 0 && count < prims.size() && cost < best.cost) best = {axis, b, cost};
    }
  }
  return best;
}

}  // namespace

Bvh build_bvh(std::span<const AABB> boxes, std::span<const vec3> centers, const BvhBuildOptions& options) {
  Bvh bvh;
  const uint32_t n = uint32_t(boxes.size());
  if (n == 0) return bvh;
  const int bin_count = std::clamp(options.bins, 2, kMaxBins);
  const uint32_t max_leaf = uint32_t(std::max(1, options.max_leaf_size));
  bvh.prim_indices.resize(n);
  std::iota(bvh.prim_indices.begin(), bvh.prim_indices.end(), 0u);
  bvh.nodes.reserve(2 * size_t(n));
  bvh.nodes.emplace_back();

  std::vector<Task> stack{{0, 0, n, 0}};
  while (!stack.empty()) {
    Task task = stack.back();
    stack.pop_back();
    bvh.depth = std::max(bvh.depth, task.depth);
    std::span<uint32_t> prims(bvh.prim_indices.data() + task.begin, task.end - task.begin);
    AABB bounds, centroid_bounds;
    for (uint32_t p : prims) {
      bounds.extend(boxes[p]);
      centroid_bounds.extend(centers[p]);
    }
    BvhNode& node = bvh.nodes[task.node];
    node.bounds = bounds;
    const uint32_t count = uint32_t(prims.size());
    auto make_leaf = [&] {
      bvh.nodes[task.node].first = task.begin;
      bvh.nodes[task.node].count = count;
    };
    if (count == 1) { make_leaf(); continue; }

    uint32_t mid = 0;
    Split split;
    if (task.depth < kSahDepthLimit) split = find_binned_split(boxes, centers, prims, centroid_bounds, bin_count);
    if (split.axis >= 0) {
      float leaf_cost = bounds.half_area() * float(count);
      float split_cost = options.traversal_cost * bounds.half_area() + split.cost;
      if (leaf_cost <= split_cost && count <= max_leaf) { make_leaf(); continue; }
      const int axis = split.axis;
      const float lo = centroid_bounds.lo[axis];
      const float scale = float(bin_count) / centroid_bounds.extent()[axis];
      auto it = std::partition(prims.begin(), prims.end(), [&](uint32_t p) {
        int b = std::clamp(int((centers[p][axis] - lo) * scale), 0, bin_count - 1);
        return b <= split.bin;
      });
      mid = uint32_t(it - prims.begin());
    }
    if (mid == 0 || mid == count) {
      // No useful SAH split (all centroids equal, or too deep): a median split keeps the tree balanced.
      if (count <= max_leaf) { make_leaf(); continue; }
      int axis = max_dimension(centroid_bounds.extent());
      mid = count / 2;
      std::nth_element(prims.begin(), prims.begin() + mid, prims.end(),
                       [&](uint32_t a, uint32_t b) { return centers[a][axis] < centers[b][axis]; });
    }
    uint32_t left = uint32_t(bvh.nodes.size());
    bvh.nodes[task.node].first = left;
    bvh.nodes[task.node].count = 0;
    bvh.nodes.emplace_back();
    bvh.nodes.emplace_back();
    stack.push_back({left + 1, task.begin + mid, task.end, task.depth + 1});
    stack.push_back({left, task.begin, task.begin + mid, task.depth + 1});
  }
  return bvh;
}

float sah_cost(const Bvh& bvh, float traversal_cost) {
  if (bvh.nodes.empty()) return 0.0f;
  double root = bvh.nodes[0].bounds.half_area();
  if (!(root > 0.0)) return 0.0f;
  double cost = 0.0;
  for (const BvhNode& node : bvh.nodes) {
    double a = node.bounds.half_area() / root;
    cost += node.is_leaf() ? a * node.count : a * traversal_cost;
  }
  return float(cost);
}

}  // namespace pt
