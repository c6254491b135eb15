/// Building the 8-wide tree from the binary one, and refitting it.
#include "accel/bvh8.h"
#include "accel/parallel.h"

#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>

namespace pt {
namespace {

AABB triangle_box(std::span<const vec3> v, uint32_t prim) {
  AABB b;
  for (int k = 0; k < 3; ++k) b.extend(v[3 * size_t(prim) + k]);
  return b;
}

AABB node_box(const Bvh8Node& node) {
  AABB b;
  for (int s = 0; s < 8; ++s)
    if (node.child[s] != kEmptyChild) b.extend(slot_box(node, s));
  return b;
}

void fill_block(Tri4& block, std::span<const vec3> vertices) {
  for (int lane = 0; lane < 4; ++lane) {
    const size_t prim = block.prim[lane] != kInvalidPrim ? block.prim[lane] : block.prim[0];
    set_lane(block, lane, vertices[3 * prim], vertices[3 * prim + 1], vertices[3 * prim + 2]);
  }
}

AABB block_box(const Tri4& block, std::span<const vec3> vertices) {
  AABB b;
  for (uint32_t prim : block.prim)
    if (prim != kInvalidPrim) b.extend(finite_or_empty(triangle_box(vertices, prim)));
  return b;
}

/// The SAH-optimal way to cut the binary tree into 8-wide nodes and leaves (Ylitie, Karras and Laine 2017,
/// "Efficient incoherent ray traversal on GPUs through compressed wide BVHs", section 4.1), by dynamic programming
/// from the leaves up. The greedy collapse (open the largest child until 8) fills the top of the tree and leaves a
/// third of the nodes near the bottom with 2 or 3 children; here a small subtree is spread into its parent's free
/// slots when that is cheaper, and the leaves of a subtree of up to 16 triangles may merge into one leaf.
struct CollapsePlan {
  /// Cost of one visit of a wide node and of one 4-triangle block test, in the same unit (measured: a block test
  /// costs about as much as a node visit with its stack and ordering work).
  static constexpr float kNodeCost = 1.0f, kBlockCost = 1.0f;
  static constexpr uint32_t kMaxLeafPrims = 4 * kMaxLeafBlocks;

  struct Entry {
    float slots[8];      ///< slots[k-1]: cheapest cover of the subtree by at most k slot roots
    uint8_t split[8];    ///< split[k-1]: 0 = the subtree is one slot; j = j slots to the left child, k - j right
    uint8_t node_split;  ///< as a wide node: slots given to the left child (of 8)
    bool leaf;           ///< as one slot: a leaf (true) or a wide node
    uint32_t first, count;  ///< its primitives, contiguous in prim_indices
  };
  HugeVector<Entry> e;

  /// Subtrees rooted kParallelDepth levels below the root are planned by the build threads in parallel, each
  /// children first, then the few nodes above them. Every entry is the same function of its children's entries,
  /// so the plan does not depend on the thread count. (Serial, the plan was the largest serial part of the
  /// collapse.)
  static constexpr int kParallelDepth = 4;

  CollapsePlan(const Bvh& binary, int threads) : e(binary.nodes.size()) {
    std::vector<uint32_t> top, roots;  // top: the nodes above the subtrees, parents before children
    std::vector<std::pair<uint32_t, int>> stack{{0u, 0}};
    while (!stack.empty()) {
      const auto [i, depth] = stack.back();
      stack.pop_back();
      if (depth == kParallelDepth || binary.nodes[i].is_leaf()) {
        roots.push_back(i);
        continue;
      }
      top.push_back(i);
      stack.push_back({binary.nodes[i].first + 1, depth + 1});
      stack.push_back({binary.nodes[i].first, depth + 1});
    }
    std::atomic<size_t> next{0};
    parallel_chunks(size_t(threads), threads, 1, [&](int, size_t, size_t) {
      std::vector<uint32_t> order;  // the subtree's nodes, parents before children
      for (size_t k; (k = next.fetch_add(1)) < roots.size();) {
        order.assign(1, roots[k]);
        for (size_t m = 0; m < order.size(); ++m)
          if (!binary.nodes[order[m]].is_leaf())
            order.insert(order.end(), {binary.nodes[order[m]].first, binary.nodes[order[m]].first + 1});
        for (size_t m = order.size(); m-- > 0;) plan_node(binary, order[m]);
      }
    });
    for (size_t m = top.size(); m-- > 0;) plan_node(binary, top[m]);
  }

  /// Entry i from its children's entries (already planned).
  void plan_node(const Bvh& binary, uint32_t i) {
    {
      const BvhNode& n = binary.nodes[i];
      Entry& x = e[i];
      // Non-finite or overflowing boxes (primitives near 1e30, empty boxes of non-finite ones) must not make every
      // comparison below false: costs saturate at infinity, and the splits keep valid defaults.
      const float raw_area = n.bounds.half_area();
      const float area = raw_area >= 0.0f && raw_area < kInfinity ? raw_area : kInfinity;
      float as_leaf = kInfinity, as_node = kInfinity;
      x.node_split = 4;
      Cover children_cover;  // the children's best covers by 2..8 slots: lane k-1 for k slots
      if (n.is_leaf()) {
        x.first = n.first;
        x.count = n.count;
      } else {
        const Entry &l = e[n.first], &r = e[n.first + 1];
        x.first = std::min(l.first, r.first);
        x.count = l.count + r.count;
        children_cover = cover_by_children(l, r);
        if (children_cover.split[7] != 0) x.node_split = uint8_t(children_cover.split[7]);
        as_node = children_cover.cost[7] + kNodeCost * area;
      }
      if (x.count <= kMaxLeafPrims) as_leaf = kBlockCost * area * float((x.count + 3) / 4);
      x.leaf = x.count <= kMaxLeafPrims && as_leaf <= as_node;  // never a leaf too big, even at infinite costs
      const float one_slot = std::min(as_leaf, as_node);
      for (int k = 1; k <= 8; ++k) {
        const bool split = k >= 2 && children_cover.cost[k - 1] < one_slot;
        x.slots[k - 1] = split ? children_cover.cost[k - 1] : one_slot;
        x.split[k - 1] = split ? uint8_t(children_cover.split[k - 1]) : 0;
      }
    }
  }

  /// The cheapest covers of a node's two children by k = 1..8 slot roots in all: cost[k-1] is the minimum over
  /// j = 1..k-1 of l.slots[j-1] + r.slots[k-j-1] (a min-plus convolution), split[k-1] the smallest j reaching it
  /// (0 and infinity for k = 1). For one j the candidates of every k are l.slots[j-1] plus r.slots shifted up by j
  /// lanes, read from a copy padded with infinities: eight lanes at once (two SSE registers) instead of 35 dependent
  /// scalar compare-and-selects, which made this DP the largest serial part of the collapse in perf.
  struct Cover {
    alignas(16) float cost[8];
    alignas(16) int32_t split[8];
    Cover() {
      std::fill(cost, cost + 8, kInfinity);
      std::fill(split, split + 8, 0);
    }
  };
  static Cover cover_by_children(const Entry& l, const Entry& r) {
    alignas(16) float padded[16];
    std::fill(padded, padded + 8, kInfinity);
    std::copy(r.slots, r.slots + 8, padded + 8);
    __m128 best[2] = {_mm_set1_ps(kInfinity), _mm_set1_ps(kInfinity)};
    __m128i arg[2] = {_mm_setzero_si128(), _mm_setzero_si128()};
    for (int j = 1; j < 8; ++j) {
      const __m128 lj = _mm_set1_ps(l.slots[j - 1]);
      const __m128i jj = _mm_set1_epi32(j);
      for (int h = 0; h < 2; ++h) {
        const __m128 c = _mm_add_ps(lj, _mm_loadu_ps(padded + 8 - j + 4 * h));
        const __m128 lower = _mm_cmplt_ps(c, best[h]);  // strict: ties keep the smaller j
        best[h] = _mm_or_ps(_mm_and_ps(lower, c), _mm_andnot_ps(lower, best[h]));
        const __m128i take = _mm_castps_si128(lower);
        arg[h] = _mm_or_si128(_mm_and_si128(take, jj), _mm_andnot_si128(take, arg[h]));
      }
    }
    Cover out;
    for (int h = 0; h < 2; ++h) {
      _mm_store_ps(out.cost + 4 * h, best[h]);
      _mm_store_si128(reinterpret_cast<__m128i*>(out.split + 4 * h), arg[h]);
    }
    return out;
  }

  /// The slot roots of binary node `index` covered by at most k slots.
  void gather(const Bvh& binary, uint32_t index, int k, uint32_t* out, int& n) const {
    const int j = e[index].split[k - 1];
    if (j == 0) {
      out[n++] = index;
      return;
    }
    gather(binary, binary.nodes[index].first, j, out, n);
    gather(binary, binary.nodes[index].first + 1, k - j, out, n);
  }
};

/// Builds the tree's structure: nodes, and blocks with their prim ids; the vertices are gathered afterwards.
struct Collapser {
  const Bvh& binary;
  const CollapsePlan& plan;
  Bvh8& out;
  HugeVector<uint32_t>& blocks;  ///< offsets of the blocks made, for the (parallel) vertex gather

  uint32_t allocate(uint32_t units) {
    const size_t offset = out.units.size();
    if (offset + units > kMaxArenaUnits) throw std::length_error("BVH larger than 16 GiB");
    out.units.resize(offset + units);
    return uint32_t(offset);
  }

  /// A leaf of the primitives of binary subtree `index` (contiguous in prim_indices).
  ChildRef make_leaf(uint32_t index) {
    const CollapsePlan::Entry& x = plan.e[index];
    const uint32_t count = (x.count + 3) / 4;
    const uint32_t first = allocate(count * kBlockUnits);
    for (uint32_t k = 0; k < count; ++k) {
      Tri4& block = out.block(first + k * kBlockUnits);
      for (uint32_t lane = 0; lane < 4; ++lane) {
        const uint32_t i = 4 * k + lane;
        block.prim[lane] = i < x.count ? binary.prim_indices[x.first + i] : kInvalidPrim;
      }
      blocks.push_back(first + k * kBlockUnits);
    }
    out.block_count += count;
    return make_leaf_ref(first, count);
  }

  /// Makes the wide node for binary node `index` and, depth first, its subtrees; returns the node's offset.
  ChildRef collapse(uint32_t index) {
    uint32_t children[8];
    int n = 0;
    const BvhNode& root = binary.nodes[index];
    if (root.is_leaf()) {
      children[n++] = index;  // a tree of one leaf: the root node has one child
    } else {
      const int j = plan.e[index].node_split;
      plan.gather(binary, root.first, j, children, n);
      plan.gather(binary, root.first + 1, 8 - j, children, n);
    }
    auto is_leaf = [&](uint32_t c) { return binary.nodes[c].is_leaf() || plan.e[c].leaf; };
    // Leaves first, so their blocks land right after this node.
    std::stable_partition(children, children + n, is_leaf);
    const uint32_t w = allocate(kNodeUnits);
    out.node_count++;
    {
      Bvh8Node& node = out.node(w);
      for (int a = 0; a < 6; ++a) std::fill(node.bounds[a], node.bounds[a] + 8, a % 2 ? -kInfinity : kInfinity);
      std::fill(node.child, node.child + 8, kEmptyChild);
    }
    for (int i = 0; i < n; ++i) {
      const ChildRef ref = is_leaf(children[i]) ? make_leaf(children[i]) : collapse(children[i]);
      Bvh8Node& node = out.node(w);  // the arena may have grown: look it up again
      set_slot(node, i, binary.nodes[children[i]].bounds);
      node.child[i] = ref;
    }
    return w;
  }
};

/// Refits the subtree at `ref` and returns its box.
AABB refit_node(Bvh8& bvh, ChildRef ref, std::span<const vec3> vertices) {
  for (int slot = 0; slot < 8; ++slot) {
    const ChildRef c = bvh.node(ref).child[slot];
    if (c == kEmptyChild) continue;
    AABB b;
    if (is_leaf_ref(c)) {
      for (uint32_t k = 0; k < leaf_count(c); ++k) {
        Tri4& block = bvh.block(leaf_first(c) + k * kBlockUnits);
        fill_block(block, vertices);
        b.extend(block_box(block, vertices));
      }
    } else {
      b = refit_node(bvh, c, vertices);
    }
    set_slot(bvh.node(ref), slot, b);
  }
  return node_box(bvh.node(ref));
}

}  // namespace

Bvh8 make_bvh8(const Bvh& binary, std::span<const vec3> triangle_vertices, int threads) {
  Bvh8 out;
  if (binary.nodes.empty()) return out;
  size_t leaves = 0;
  for (const BvhNode& n : binary.nodes) leaves += n.is_leaf();
  // About one wide node per 4 binary interior nodes, and up to ceil(n/4) + leaves blocks.
  out.units.reserve(kNodeUnits * (binary.nodes.size() / 4 + 2) +
                    kBlockUnits * (binary.prim_indices.size() / 4 + leaves));
  HugeVector<uint32_t> blocks;
  blocks.reserve(binary.prim_indices.size() / 4 + leaves);
  const CollapsePlan plan(binary, threads);
  Collapser{binary, plan, out, blocks}.collapse(0);
  // Gathering the vertices is most of the collapse's time (random reads): in parallel.
  parallel_chunks(blocks.size(), threads, 2048, [&](int, size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) fill_block(out.block(blocks[k]), triangle_vertices);
  });
  return out;
}

void refit_bvh8(Bvh8& bvh, std::span<const vec3> triangle_vertices) {
  if (!bvh.empty()) refit_node(bvh, 0, triangle_vertices);
}

AABB bvh8_bounds(const Bvh8& bvh) { return bvh.empty() ? AABB{} : node_box(bvh.node(0)); }

}  // namespace pt
