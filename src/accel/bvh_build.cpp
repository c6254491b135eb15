/// Binned SAH BVH construction (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies";
/// pbrt-v4 section 7.3.2), with the top levels built in parallel.
///
/// Speed comes from three habits of fast builders (Embree, madmann91/bvh): the primitive references are one
/// contiguous array that is partitioned in place, so every pass reads memory in order; one pass bins all three
/// axes; and the partition collects both children's box and centroid bounds as it goes, so no node needs a
/// separate bounds pass.
#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <thread>

#include "accel/bvh.h"

namespace pt {
namespace {

constexpr int kMaxBins = 64;
/// Below this depth the SAH decides; beyond it splits are median splits so the depth stays bounded.
constexpr int kSahDepthLimit = kBvhMaxDepth - 32;
/// Subtrees smaller than this are built by the thread that made them.
constexpr uint32_t kMinParallelPrims = 4096;

/// A box as two SSE registers (the w lanes are ignored): one min and one max per extend.
struct Box4 {
  __m128 lo = _mm_set1_ps(kInfinity), hi = _mm_set1_ps(-kInfinity);
  void extend(const Box4& b) { lo = _mm_min_ps(lo, b.lo); hi = _mm_max_ps(hi, b.hi); }
  void extend_point(__m128 p) { lo = _mm_min_ps(lo, p); hi = _mm_max_ps(hi, p); }
  float half_area() const {
    alignas(16) float e[4];
    _mm_store_ps(e, _mm_max_ps(_mm_sub_ps(hi, lo), _mm_setzero_ps()));
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  }
  AABB aabb() const {
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    return {vec3(l[0], l[1], l[2]), vec3(h[0], h[1], h[2])};
  }
};

/// A primitive reference: its box, centroid and id, moved together by the partition.
struct alignas(16) PrimRef {
  Box4 box;
  __m128 center;
  uint32_t id;
  float center_axis(int a) const {
    alignas(16) float c[4];
    _mm_store_ps(c, center);
    return c[a];
  }
};

/// Bounds of a set of references and of their centroids.
struct RangeBounds {
  Box4 box, centroids;
  void extend(const PrimRef& r) { box.extend(r.box); centroids.extend_point(r.center); }
  void extend(const RangeBounds& o) { box.extend(o.box); centroids.extend(o.centroids); }
};

struct Bin {
  Box4 box;
  uint32_t count = 0;
};

struct Split {
  int axis = -1;
  int bin = 0;  ///< primitives in bins [0, bin] go left
  float cost = kInfinity;
};

struct Builder {
  std::span<PrimRef> refs;
  const BvhBuildOptions& options;
  int max_bins;
  uint32_t max_leaf;
  std::atomic<int> depth{0};

  struct Task {
    uint32_t node, begin, end;
    int depth;
    RangeBounds bounds;
  };

  float blocks(uint32_t count) const { return sah_leaf_tests(count, options); }

  /// Small nodes get fewer bins: with as many bins as primitives the binned split is already close to a sweep.
  int bins_for(uint32_t count) const { return std::clamp(int(count), std::min(8, max_bins), max_bins); }

  /// Bin index of every reference on all three axes at once.
  struct Binning {
    __m128 lo, scale;
    int bins;
    __m128i index(const PrimRef& r) const {
      const __m128 f = _mm_mul_ps(_mm_sub_ps(r.center, lo), scale);  // clamped before the conversion; NaN -> 0
      return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), _mm_set1_ps(float(bins - 1))));
    }
    int index(const PrimRef& r, int axis) const {
      alignas(16) int32_t b[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(b), index(r));
      return b[axis];
    }
  };

  Binning make_binning(const Task& t) const {
    const int bins = bins_for(t.end - t.begin);
    const __m128 extent = _mm_sub_ps(t.bounds.centroids.hi, t.bounds.centroids.lo);
    // scale = bins / extent where extent > 0, else 0 (everything in bin 0)
    const __m128 positive = _mm_cmpgt_ps(extent, _mm_setzero_ps());
    const __m128 scale = _mm_and_ps(positive, _mm_div_ps(_mm_set1_ps(float(bins)), extent));
    return {t.bounds.centroids.lo, scale, bins};
  }

  Split find_split(const Task& t, const Binning& binning, Bin (*bins)[kMaxBins]) const {
    const int n_bins = binning.bins;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < n_bins; ++b) bins[a][b] = Bin{};
    for (uint32_t i = t.begin; i < t.end; ++i) {
      const PrimRef& r = refs[i];
      alignas(16) int32_t idx[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(idx), binning.index(r));
      for (int a = 0; a < 3; ++a) {
        Bin& b = bins[a][idx[a]];
        b.box.extend(r.box);
        b.count++;
      }
    }
    Split best;
    const uint32_t count = t.end - t.begin;
    alignas(16) float extent[4];
    _mm_store_ps(extent, _mm_sub_ps(t.bounds.centroids.hi, t.bounds.centroids.lo));
    for (int a = 0; a < 3; ++a) {
      if (!(extent[a] > 0.0f)) continue;
      // Sweep from the right to get the cost of every right side, then from the left.
      float right_cost[kMaxBins];
      Box4 acc;
      uint32_t n = 0;
      for (int b = n_bins - 1; b > 0; --b) {
        acc.extend(bins[a][b].box);
        n += bins[a][b].count;
        right_cost[b - 1] = acc.half_area() * blocks(n);
      }
      acc = Box4{};
      n = 0;
      for (int b = 0; b < n_bins - 1; ++b) {
        acc.extend(bins[a][b].box);
        n += bins[a][b].count;
        const float cost = acc.half_area() * blocks(n) + right_cost[b];
        if (n > 0 && n < count && cost < best.cost) best = {a, b, cost};
      }
    }
    return best;
  }

  RangeBounds bounds_of(uint32_t begin, uint32_t end) const {
    RangeBounds b;
    for (uint32_t i = begin; i < end; ++i) b.extend(refs[i]);
    return b;
  }

  /// Splits a task in two, or returns false to make it a leaf.
  bool split(const Task& t, Task& left, Task& right, Bin (*bins)[kMaxBins]) const {
    const uint32_t count = t.end - t.begin;
    if (count == 1) return false;
    Split s;
    const Binning binning = make_binning(t);
    if (t.depth < kSahDepthLimit) s = find_split(t, binning, bins);
    uint32_t mid = t.begin;
    if (s.axis >= 0) {
      const float area = t.bounds.box.half_area();
      if (area * blocks(count) <= options.traversal_cost * area + s.cost && count <= max_leaf) return false;
      // Partition in place, collecting both sides' box and centroid bounds on the way.
      const int a = s.axis;
      RangeBounds lb, rb;
      uint32_t i = t.begin, j = t.end;
      for (;;) {
        while (i < j && binning.index(refs[i], a) <= s.bin) lb.extend(refs[i++]);
        while (i < j && binning.index(refs[j - 1], a) > s.bin) rb.extend(refs[--j]);
        if (i == j) break;
        std::swap(refs[i], refs[j - 1]);
      }
      mid = i;
      left = {0, t.begin, mid, t.depth + 1, lb};
      right = {0, mid, t.end, t.depth + 1, rb};
    }
    if (mid == t.begin || mid == t.end) {
      // No useful SAH split (all centroids equal, or too deep): a median split keeps the tree balanced.
      if (count <= max_leaf) return false;
      alignas(16) float extent[4];
      _mm_store_ps(extent, _mm_sub_ps(t.bounds.centroids.hi, t.bounds.centroids.lo));
      const int a = max_dimension(vec3(extent[0], extent[1], extent[2]));
      mid = t.begin + count / 2;
      std::nth_element(refs.begin() + t.begin, refs.begin() + mid, refs.begin() + t.end,
                       [&](const PrimRef& x, const PrimRef& y) { return x.center_axis(a) < y.center_axis(a); });
      left = {0, t.begin, mid, t.depth + 1, bounds_of(t.begin, mid)};
      right = {0, mid, t.end, t.depth + 1, bounds_of(mid, t.end)};
    }
    return true;
  }

  /// Builds the subtree of `root` (a task whose node is nodes[root.node]) into `nodes`. Big nodes hand their right
  /// child to a new thread while `spare_threads` > 0; that thread builds into its own vector (no shared counter, no
  /// false sharing), which is appended here after the join with its child indices shifted.
  void build(Task root, int spare_threads, std::vector<BvhNode>& nodes) {
    struct Handoff {
      uint32_t slot;  ///< the placeholder node in `nodes` the subtree's root replaces
      std::vector<BvhNode> nodes;
      std::thread thread;
    };
    std::vector<std::unique_ptr<Handoff>> handoffs;
    std::vector<Task> stack{root};
    Bin bins[3][kMaxBins];  // scratch, reused by every node this thread splits
    int local_depth = 0;
    while (!stack.empty()) {
      Task t = stack.back();
      stack.pop_back();
      local_depth = std::max(local_depth, t.depth);
      nodes[t.node].bounds = t.bounds.box.aabb();
      Task left, right;
      if (!split(t, left, right, bins)) {
        nodes[t.node].first = t.begin;
        nodes[t.node].count = t.end - t.begin;
        continue;
      }
      const uint32_t first = uint32_t(nodes.size());
      nodes[t.node].first = first;
      nodes[t.node].count = 0;
      nodes.emplace_back();
      nodes.emplace_back();
      left.node = first;
      right.node = first + 1;
      if (spare_threads > 0 && std::min(left.end - left.begin, right.end - right.begin) >= kMinParallelPrims) {
        const int give = (spare_threads + 1) / 2;  // the new thread takes half of the spare threads with it
        spare_threads -= give;
        auto h = std::make_unique<Handoff>();
        h->slot = right.node;
        h->nodes.reserve(2 * size_t(right.end - right.begin));
        h->nodes.emplace_back();
        right.node = 0;
        h->thread = std::thread([this, right, give, hp = h.get()] { build(right, give - 1, hp->nodes); });
        handoffs.push_back(std::move(h));
      } else {
        stack.push_back(right);
      }
      stack.push_back(left);
    }
    for (auto& h : handoffs) {
      h->thread.join();
      const uint32_t base = uint32_t(nodes.size()) - 1;  // sub-tree node i >= 1 goes to base + i
      auto moved = [&](BvhNode n) {
        if (!n.is_leaf()) n.first += base;
        return n;
      };
      nodes[h->slot] = moved(h->nodes[0]);
      for (size_t i = 1; i < h->nodes.size(); ++i) nodes.push_back(moved(h->nodes[i]));
    }
    int d = depth.load();
    while (local_depth > d && !depth.compare_exchange_weak(d, local_depth)) {}
  }
};

}  // namespace

Bvh build_bvh(std::span<const AABB> boxes, std::span<const vec3> centers, const BvhBuildOptions& options) {
  Bvh bvh;
  const uint32_t n = uint32_t(boxes.size());
  if (n == 0) return bvh;
  std::vector<PrimRef> refs(n);
  RangeBounds all;
  for (uint32_t i = 0; i < n; ++i) {
    const AABB b = finite_or_empty(boxes[i]);
    const vec3 c = is_finite(centers[i]) ? centers[i] : vec3(0.0f);  // no NaN in the bins or the median's order
    refs[i].box = {_mm_setr_ps(b.lo.x, b.lo.y, b.lo.z, 0.0f), _mm_setr_ps(b.hi.x, b.hi.y, b.hi.z, 0.0f)};
    refs[i].center = _mm_setr_ps(c.x, c.y, c.z, 0.0f);
    refs[i].id = i;
    all.extend(refs[i]);
  }
  bvh.nodes.reserve(2 * size_t(n));
  bvh.nodes.emplace_back();
  Builder b{refs,
            options,
            std::clamp(options.bins, 2, kMaxBins),
            uint32_t(std::max(1, options.max_leaf_size))};
  int threads = options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  b.build({0, 0, n, 0, all}, threads - 1, bvh.nodes);
  bvh.depth = b.depth.load();
  bvh.prim_indices.resize(n);
  for (uint32_t i = 0; i < n; ++i) bvh.prim_indices[i] = refs[i].id;
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
