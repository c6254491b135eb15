#pragma once
/// An 8-wide BVH over triangles, collapsed from the binary SAH tree, with SIMD node tests and 4-triangle leaf
/// blocks (the layout of Embree's BVH8, Wald et al. 2014, "Embree: a kernel framework for efficient CPU ray
/// tracing"), collapsed from the binary tree by the SAH-optimal dynamic program of Ylitie, Karras and Laine 2017
/// ("Efficient incoherent ray traversal on GPUs through compressed wide BVHs"). One node test checks a ray against 8
/// boxes at once, so a ray visits about a third as many nodes as in the binary tree, and each visit is a few AVX
/// instructions.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "accel/bvh.h"
#include "core/huge_page_allocator.h"

namespace pt {

/// A child reference: an interior node's offset in the arena, or (bit 31 set) a leaf of `count` (1 to 4)
/// consecutive 4-triangle blocks from offset `first`. Offsets count 32-byte units.
using ChildRef = uint32_t;
inline constexpr ChildRef kLeafBit = 0x80000000u;
inline constexpr ChildRef kEmptyChild = 0xffffffffu;  ///< an unused slot (its box is empty, so never entered)
inline constexpr uint32_t kMaxLeafBlocks = 4;
inline constexpr uint32_t kMaxArenaUnits = 1u << 29;  ///< 16 GiB of tree: offsets have 29 bits
inline bool is_leaf_ref(ChildRef r) { return (r & kLeafBit) != 0; }
inline ChildRef make_leaf_ref(uint32_t first_unit, uint32_t block_count) {
  return kLeafBit | ((block_count - 1) << 29) | first_unit;
}
inline uint32_t leaf_first(ChildRef r) { return r & (kMaxArenaUnits - 1); }
inline uint32_t leaf_count(ChildRef r) { return ((r >> 29) & 3u) + 1; }

/// 224 bytes: the boxes of 8 children as structure of arrays, bounds[2 * axis + side][child] with side 0 the
/// low and 1 the high plane, so a ray picks its near and far planes per axis by index, without a branch.
struct alignas(32) Bvh8Node {
  float bounds[6][8];
  ChildRef child[8];
};

/// Writes and reads the box of child `slot`.
inline void set_slot(Bvh8Node& node, int slot, const AABB& b) {
  for (int a = 0; a < 3; ++a) {
    node.bounds[2 * a][slot] = b.lo[a];
    node.bounds[2 * a + 1][slot] = b.hi[a];
  }
}
inline AABB slot_box(const Bvh8Node& node, int slot) {
  AABB b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = node.bounds[2 * a][slot];
    b.hi[a] = node.bounds[2 * a + 1][slot];
  }
  return b;
}

/// 160 bytes: four triangles as structure of arrays, v[vertex][axis][lane], so the watertight test runs on 4 lanes
/// and a ray reads its permuted axes (kx, ky, kz) directly. Unused lanes repeat lane 0 and have prim = kInvalidPrim.
struct alignas(32) Tri4 {
  float v[3][3][4];
  uint32_t prim[4];
};
inline constexpr uint32_t kInvalidPrim = 0xffffffffu;

/// Vertex k of a block's lane given as &v[0][0][lane]: v[k][a][lane] lies 12 k + 4 a floats further.
inline vec3 lane_vertex(const float* lane, int k) { return vec3(lane[12 * k], lane[12 * k + 4], lane[12 * k + 8]); }

/// The prim id of a block's lane given as &v[0][0][lane]: prim[lane] lies offsetof(Tri4, prim) bytes further.
inline uint32_t lane_prim(const float* lane) {
  uint32_t prim;
  std::memcpy(&prim, reinterpret_cast<const char*>(lane) + offsetof(Tri4, prim), sizeof prim);
  return prim;
}

/// Writes triangle (p0, p1, p2) into `lane` (the prim id is set separately).
inline void set_lane(Tri4& block, int lane, vec3 p0, vec3 p1, vec3 p2) {
  const vec3 p[3] = {p0, p1, p2};
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) block.v[k][a][lane] = p[k][a];
}

/// The unit of the arena: nodes take 7, blocks 5.
struct alignas(32) Bvh8Unit {
  float f[8];
};
inline constexpr uint32_t kNodeUnits = sizeof(Bvh8Node) / sizeof(Bvh8Unit);
inline constexpr uint32_t kBlockUnits = sizeof(Tri4) / sizeof(Bvh8Unit);
static_assert(sizeof(Bvh8Node) % sizeof(Bvh8Unit) == 0 && sizeof(Tri4) % sizeof(Bvh8Unit) == 0);

/// Nodes and leaf blocks share one array, in depth-first order with a node's leaves right after it: a leaf is
/// usually in the same DRAM page as its parent, which measurably shortens the memory stalls of incoherent rays.
struct Bvh8 {
  std::vector<Bvh8Unit, HugePageAllocator<Bvh8Unit>> units;  ///< the root node is at offset 0
  size_t node_count = 0, block_count = 0;

  bool empty() const { return units.empty(); }
  const Bvh8Node& node(ChildRef r) const { return *reinterpret_cast<const Bvh8Node*>(&units[r]); }
  Bvh8Node& node(ChildRef r) { return *reinterpret_cast<Bvh8Node*>(&units[r]); }
  const Tri4& block(uint32_t unit) const { return *reinterpret_cast<const Tri4*>(&units[unit]); }
  Tri4& block(uint32_t unit) { return *reinterpret_cast<Tri4*>(&units[unit]); }
  size_t bytes() const { return units.size() * sizeof(Bvh8Unit); }
};

/// Collapses `binary` (built over the triangles; triangle i is vertices 3i..3i+2) into an 8-wide tree: the cut into
/// wide nodes and leaves (of up to 16 triangles, ceil(count / 4) blocks) that minimizes the SAH cost of the wide
/// tree. Measured against the greedy collapse (open the largest child until 8): half the nodes on the 1M knot and
/// 8-12% faster rays there; on the bunny diffuse and primary rays 2-5% faster, shadow rays up to 8% slower. Throws
/// std::length_error beyond kMaxArenaUnits (16 GiB of tree, about 250M triangles: more than memory allows anyway), as
/// std::vector throws std::bad_alloc. The leaf blocks are filled on up to `threads` threads; the result does not depend
/// on the count.
Bvh8 make_bvh8(const Bvh& binary, std::span<const vec3> triangle_vertices, int threads = 1);

/// Rewrites the triangle data and all boxes after the vertices moved, keeping the topology.
void refit_bvh8(Bvh8& bvh, std::span<const vec3> triangle_vertices);

/// Bounds of everything in the tree.
AABB bvh8_bounds(const Bvh8& bvh);

/// Per-ray data of the node test: origin, reciprocal direction, and which plane is near per axis.
/// With FMA (kNodeTestFma) a slab distance is one fused b * inv - org * inv. The product org * inv is rounded,
/// an absolute error Ize's relative bound does not cover, so it is replaced by org_inv_near = org * inv + err and
/// org_inv_far = org * inv - err, err >= twice its rounding error: near distances only get smaller and far ones
/// larger. Without FMA a distance is (b - org) * inv, as in intersect_box.
/// Far planes use inv_dir_far = inv_dir * kFarScale: Ize's scaling of far distances by 1 + 2 gamma(3) (about 6
/// ulps) folded into the reciprocal, with margin (16 ulps, and an err of 16 ulps of org * inv_dir_far instead of 4),
/// so every far distance is at least what the separate multiplication after the min gave. The node test then has
/// no multiplication between its min and its compare: 4 cycles less latency per node (shadow rays 4-5% faster).
inline constexpr float kFarScale = 1.0f + 0x1p-20f;
struct NodeRay {
  float org[3], inv_dir[3], inv_dir_far[3];
  float org_inv_near[3], org_inv_far[3];
  int near[3], far[3];  ///< indices into Bvh8Node::bounds
};
#if defined(__FMA__)
inline constexpr bool kNodeTestFma = true;
#else
inline constexpr bool kNodeTestFma = false;
#endif
inline NodeRay make_node_ray(const Ray& ray) {
  NodeRay r;
  for (int a = 0; a < 3; ++a) {
    r.org[a] = ray.org[a];
    r.inv_dir[a] = ray.dir[a] != 0.0f ? 1.0f / ray.dir[a] : std::copysign(kInfinity, ray.dir[a]);
    r.inv_dir_far[a] = r.inv_dir[a] * kFarScale;
    const float oi = r.org[a] * r.inv_dir[a];  // inf or NaN when inv_dir is infinite: then the axis never culls
    r.org_inv_near[a] = oi + (std::abs(oi) * 0x1p-22f + 0x1p-126f);
    const float oi_far = r.org[a] * r.inv_dir_far[a];
    r.org_inv_far[a] = oi_far - (std::abs(oi_far) * 0x1p-20f + 0x1p-126f);
    const int neg = r.inv_dir[a] < 0.0f;
    r.near[a] = 2 * a + neg;
    r.far[a] = 2 * a + 1 - neg;
  }
  return r;
}

/// Tests the ray against the 8 boxes of `node` for t in [0, tmax]; returns a bit mask of the boxes hit and their
/// entry distances in `tnear`. Robust as intersect_box (Ize 2013): tmax is scaled by 1 + 2 gamma(3), far
/// distances by kFarScale (NodeRay), and NaN (0 * inf) distances leave the interval as it was; it never misses a box
/// intersect_box hits. The scalar version is the reference the SIMD one (AVX, or two SSE halves) must equal bit for
/// bit.
uint32_t intersect_node8_scalar(const Bvh8Node& node, const NodeRay& ray, float tmax, float tnear[8]);
uint32_t intersect_node8(const Bvh8Node& node, const NodeRay& ray, float tmax, float tnear[8]);

/// Name of the SIMD path compiled in ("avx", "sse" or "scalar"), for stats.
const char* bvh8_simd_name();

/// Result of a leaf-block test: the closest hit's lane or -1, with its distance and barycentrics (b1, b2).
struct Tri4Hit {
  int lane = -1;
  float t = kInfinity, b1 = 0, b2 = 0;
};

/// Per-ray data of the watertight test (see triangle.h), broadcast once per ray.
struct WatertightRay;
/// Closest hit of the block in (0, tmax); equals intersect_triangle on each lane bit for bit.
Tri4Hit intersect_tri4(const Tri4& block, const WatertightRay& ray, float tmax);
/// True if any triangle of the block is hit in (0, tmax).
bool occluded_tri4(const Tri4& block, const WatertightRay& ray, float tmax);

/// Closest hit in (0, ray.tmax): shrinks ray.tmax and sets prim, b1, b2 on a hit, and *vertices (if given) to the
/// hit triangle's lane of its leaf block, &Tri4::v[0][0][lane].
bool intersect_bvh8(const Bvh8& bvh, Ray& ray, uint32_t& prim, float& b1, float& b2,
                    const float** vertices = nullptr);
/// Any hit in (0, ray.tmax).
bool occluded_bvh8(const Bvh8& bvh, const Ray& ray);

}  // namespace pt
