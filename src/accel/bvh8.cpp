/// Building the 8-wide tree from the binary one, and refitting it.
#include "accel/bvh8.h"

#include <algorithm>

namespace pt {
namespace {

AABB triangle_box(std::span<const vec3> v, uint32_t prim) {
  AABB b;
  for (int k = 0; k < 3; ++k) b.extend(v[3 * size_t(prim) + k]);
  return b;
}

void set_slot(Bvh8Node& node, int slot, const AABB& b) {
  for (int a = 0; a < 3; ++a) {
    node.bounds[2 * a][slot] = b.lo[a];
    node.bounds[2 * a + 1][slot] = b.hi[a];
  }
}

AABB slot_box(const Bvh8Node& node, int slot) {
  AABB b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = node.bounds[2 * a][slot];
    b.hi[a] = node.bounds[2 * a + 1][slot];
  }
  return b;
}

void fill_block(Tri4& block, std::span<const vec3> vertices) {
  for (int lane = 0; lane < 4; ++lane) {
    const uint32_t prim = block.prim[lane] != kInvalidPrim ? block.prim[lane] : block.prim[0];
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) block.v[k][a][lane] = vertices[3 * size_t(prim) + k][a];
  }
}

AABB block_box(const Tri4& block, std::span<const vec3> vertices) {
  AABB b;
  for (uint32_t prim : block.prim)
    if (prim != kInvalidPrim) b.extend(triangle_box(vertices, prim));
  return b;
}

struct Collapser {
  const Bvh& binary;
  std::span<const vec3> vertices;
  Bvh8& out;

  ChildRef make_leaf(const BvhNode& leaf) {
    const uint32_t first = uint32_t(out.blocks.size());
    const uint32_t count = (leaf.count + 3) / 4;
    for (uint32_t k = 0; k < count; ++k) {
      Tri4 block;
      for (uint32_t lane = 0; lane < 4; ++lane) {
        const uint32_t i = 4 * k + lane;
        block.prim[lane] = i < leaf.count ? binary.prim_indices[leaf.first + i] : kInvalidPrim;
      }
      fill_block(block, vertices);
      out.blocks.push_back(block);
    }
    return make_leaf_ref(first, count);
  }

  /// Makes the wide node for binary node `index` and, depth first, its subtrees; returns the wide node's index.
  uint32_t collapse(uint32_t index) {
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
    const uint32_t w = uint32_t(out.nodes.size());
    out.nodes.emplace_back();
    for (int a = 0; a < 6; ++a) std::fill(out.nodes[w].bounds[a], out.nodes[w].bounds[a] + 8, a % 2 ? -kInfinity : kInfinity);
    std::fill(out.nodes[w].child, out.nodes[w].child + 8, kEmptyChild);
    for (int i = 0; i < n; ++i) {
      const BvhNode& c = binary.nodes[children[i]];
      const ChildRef ref = c.is_leaf() ? make_leaf(c) : collapse(children[i]);
      set_slot(out.nodes[w], i, c.bounds);  // out.nodes may have grown: index again
      out.nodes[w].child[i] = ref;
    }
    return w;
  }
};

}  // namespace

Bvh8 make_bvh8(const Bvh& binary, std::span<const vec3> triangle_vertices) {
  Bvh8 out;
  if (binary.nodes.empty()) return out;
  size_t leaves = 0;
  for (const BvhNode& n : binary.nodes) leaves += n.is_leaf();
  out.nodes.reserve(binary.nodes.size() / 4 + 1);
  out.blocks.reserve(binary.prim_indices.size() / 2 + leaves);
  Collapser{binary, triangle_vertices, out}.collapse(0);
  return out;
}

void refit_bvh8(Bvh8& bvh, std::span<const vec3> triangle_vertices) {
  for (Tri4& block : bvh.blocks) fill_block(block, triangle_vertices);
  for (size_t i = bvh.nodes.size(); i-- > 0;) {  // children have larger indices: a reverse sweep sees them first
    Bvh8Node& node = bvh.nodes[i];
    for (int slot = 0; slot < 8; ++slot) {
      const ChildRef ref = node.child[slot];
      if (ref == kEmptyChild) continue;
      AABB b;
      if (is_leaf_ref(ref)) {
        for (uint32_t k = 0; k < leaf_count(ref); ++k) b.extend(block_box(bvh.blocks[leaf_first(ref) + k], triangle_vertices));
      } else {
        for (int s = 0; s < 8; ++s)
          if (bvh.nodes[ref].child[s] != kEmptyChild) b.extend(slot_box(bvh.nodes[ref], s));
      }
      set_slot(node, slot, b);
    }
  }
}

AABB bvh8_bounds(const Bvh8& bvh) {
  AABB b;
  if (bvh.nodes.empty()) return b;
  for (int s = 0; s < 8; ++s)
    if (bvh.nodes[0].child[s] != kEmptyChild) b.extend(slot_box(bvh.nodes[0], s));
  return b;
}

}  // namespace pt
