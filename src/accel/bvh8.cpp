/// Building the 8-wide tree from the binary one, and refitting it.
#include "accel/bvh8.h"
#include "accel/parallel.h"

#include <algorithm>
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

/// Builds the tree's structure: nodes, and blocks with their prim ids; the vertices are gathered afterwards.
struct Collapser {
  const Bvh& binary;
  Bvh8& out;
  std::vector<uint32_t>& blocks;  ///< offsets of the blocks made, for the (parallel) vertex gather

  uint32_t allocate(uint32_t units) {
    const size_t offset = out.units.size();
    if (offset + units > kMaxArenaUnits) throw std::length_error("BVH larger than 16 GiB");
    out.units.resize(offset + units);
    return uint32_t(offset);
  }

  ChildRef make_leaf(const BvhNode& leaf) {
    const uint32_t count = (leaf.count + 3) / 4;
    const uint32_t first = allocate(count * kBlockUnits);
    for (uint32_t k = 0; k < count; ++k) {
      Tri4& block = out.block(first + k * kBlockUnits);
      for (uint32_t lane = 0; lane < 4; ++lane) {
        const uint32_t i = 4 * k + lane;
        block.prim[lane] = i < leaf.count ? binary.prim_indices[leaf.first + i] : kInvalidPrim;
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
      children[n++] = index;
    } else {
      children[n++] = root.first;
      children[n++] = root.first + 1;
    }
    while (n < 8) {
      int open = -1;
      float largest = -1.0f;
      for (int i = 0; i < n; ++i) {
        const BvhNode& c = binary.nodes[children[i]];
        if (!c.is_leaf() && c.bounds.half_area() > largest) largest = c.bounds.half_area(), open = i;
      }
      if (open < 0) break;
      const uint32_t first = binary.nodes[children[open]].first;
      children[open] = first;
      children[n++] = first + 1;
    }
    // Leaves first, so their blocks land right after this node.
    std::stable_partition(children, children + n, [&](uint32_t c) { return binary.nodes[c].is_leaf(); });
    const uint32_t w = allocate(kNodeUnits);
    out.node_count++;
    {
      Bvh8Node& node = out.node(w);
      for (int a = 0; a < 6; ++a) std::fill(node.bounds[a], node.bounds[a] + 8, a % 2 ? -kInfinity : kInfinity);
      std::fill(node.child, node.child + 8, kEmptyChild);
    }
    for (int i = 0; i < n; ++i) {
      const BvhNode& c = binary.nodes[children[i]];
      const ChildRef ref = c.is_leaf() ? make_leaf(c) : collapse(children[i]);
      Bvh8Node& node = out.node(w);  // the arena may have grown: look it up again
      set_slot(node, i, c.bounds);
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
  std::vector<uint32_t> blocks;
  blocks.reserve(binary.prim_indices.size() / 4 + leaves);
  Collapser{binary, out, blocks}.collapse(0);
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
