/// Ray traversal of the 8-wide BVH: SIMD node and leaf tests, ordered front-to-back with a small stack, early exit
/// for shadow rays. Everything the inner loop calls is inline in this file: no virtual call, no std::function, no
/// allocation.
#include <immintrin.h>

#include <algorithm>
#include <bit>

#include "accel/bvh8.h"
#include "accel/triangle.h"

#define PT_INLINE inline __attribute__((always_inline))

namespace pt {
namespace {

constexpr float kRobust = 1.0f + 2.0f * gamma_bound(3);

inline uint32_t node_test_scalar(const Bvh8Node& node, const NodeRay& r, float tmax, float tnear[8]) {
  uint32_t mask = 0;
  for (int i = 0; i < 8; ++i) {
    float t0 = 0.0f, t1 = tmax * kRobust;  // far distances come scaled by kFarScale (NodeRay)
    for (int a = 0; a < 3; ++a) {
      float near, far;
      if constexpr (kNodeTestFma) {
        near = std::fma(node.bounds[r.near[a]][i], r.inv_dir[a], -r.org_inv_near[a]);
        far = std::fma(node.bounds[r.far[a]][i], r.inv_dir_far[a], -r.org_inv_far[a]);
      } else {
        near = (node.bounds[r.near[a]][i] - r.org[a]) * r.inv_dir[a];
        far = (node.bounds[r.far[a]][i] - r.org[a]) * r.inv_dir_far[a];
      }
      t0 = near > t0 ? near : t0;  // a NaN distance leaves the interval unchanged
      t1 = far < t1 ? far : t1;
    }
    tnear[i] = t0;
    mask |= uint32_t(t0 <= t1) << i;
  }
  return mask;
}

/// The per-ray values of the node test, broadcast once per ray so the node loop only loads and computes.
#if defined(__AVX__)
using VFloat = __m256;
#define PT_V(op) _mm256_##op
constexpr const char* kSimdName = "avx";
#elif defined(__SSE2__)
using VFloat = __m128;
#define PT_V(op) _mm_##op
constexpr const char* kSimdName = "sse";
#endif

#if defined(__SSE2__)
constexpr int kLanes = sizeof(VFloat) / sizeof(float);
struct SimdNodeRay {
  VFloat org[3], inv[3], inv_far[3], org_inv_near[3], org_inv_far[3];
  int near[3], far[3];
  explicit SimdNodeRay(const NodeRay& r) {
    for (int a = 0; a < 3; ++a) {
      org[a] = PT_V(set1_ps)(r.org[a]);
      org_inv_near[a] = PT_V(set1_ps)(r.org_inv_near[a]);
      org_inv_far[a] = PT_V(set1_ps)(r.org_inv_far[a]);
      inv[a] = PT_V(set1_ps)(r.inv_dir[a]);
      inv_far[a] = PT_V(set1_ps)(r.inv_dir_far[a]);
      near[a] = r.near[a];
      far[a] = r.far[a];
    }
  }
};

/// Same operations as node_test_scalar, kLanes boxes at a time (AVX: all 8; SSE: two halves).
PT_INLINE uint32_t node_test_simd(const Bvh8Node& node, const SimdNodeRay& r, float tmax, float tnear[8]) {
  uint32_t mask = 0;
  for (int h = 0; h < 8; h += kLanes) {
    VFloat t0 = PT_V(setzero_ps)(), t1 = PT_V(set1_ps)(tmax * kRobust);
    for (int a = 0; a < 3; ++a) {
#if defined(__FMA__)
      const VFloat near = PT_V(fmsub_ps)(PT_V(load_ps)(node.bounds[r.near[a]] + h), r.inv[a], r.org_inv_near[a]);
      const VFloat far = PT_V(fmsub_ps)(PT_V(load_ps)(node.bounds[r.far[a]] + h), r.inv_far[a], r.org_inv_far[a]);
#else
      const VFloat near = PT_V(mul_ps)(PT_V(sub_ps)(PT_V(load_ps)(node.bounds[r.near[a]] + h), r.org[a]), r.inv[a]);
      const VFloat far = PT_V(mul_ps)(PT_V(sub_ps)(PT_V(load_ps)(node.bounds[r.far[a]] + h), r.org[a]), r.inv_far[a]);
#endif
      t0 = PT_V(max_ps)(near, t0);  // max/min return the second operand when the first is NaN
      t1 = PT_V(min_ps)(far, t1);
    }
    PT_V(storeu_ps)(tnear + h, t0);
#if defined(__AVX__)
    mask |= uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(t0, t1, _CMP_LE_OQ))) << h;
#else
    mask |= uint32_t(_mm_movemask_ps(_mm_cmple_ps(t0, t1))) << h;
#endif
  }
  return mask;
}
#else
using SimdNodeRay = NodeRay;
constexpr const char* kSimdName = "scalar";
PT_INLINE uint32_t node_test_simd(const Bvh8Node& node, const NodeRay& r, float tmax, float tnear[8]) {
  return node_test_scalar(node, r, tmax, tnear);
}
#endif

/// Starts loading a child the traversal will visit later.
PT_INLINE void prefetch_child(const Bvh8& bvh, ChildRef ref) {
  // leaf_first strips the leaf bit and count: what is left is the arena offset, of a node or of a leaf alike.
  const char* p = reinterpret_cast<const char*>(&bvh.units[leaf_first(ref)]);
  for (int line = 0; line < 4; ++line) _mm_prefetch(p + 64 * line, _MM_HINT_T0);
}

/// The watertight test of triangle.h on the 4 lanes of a block, with the same operations in the same order, so
/// each lane's result equals intersect_triangle's bit for bit. Returns the mask of lanes hit; fills t, b1, b2.
/// The per-ray values of the watertight test, broadcast once per ray (as SimdNodeRay): the leaf test then starts
/// with its loads.
struct SimdWatertightRay {
  const WatertightRay& w;
  __m128 ox, oy, oz, sx, sy, sz;
  explicit SimdWatertightRay(const WatertightRay& r)
      : w(r),
        ox(_mm_set1_ps(r.org[r.kx])),
        oy(_mm_set1_ps(r.org[r.ky])),
        oz(_mm_set1_ps(r.org[r.kz])),
        sx(_mm_set1_ps(r.sx)),
        sy(_mm_set1_ps(r.sy)),
        sz(_mm_set1_ps(r.sz)) {}
};

PT_INLINE int tri4_test(const Tri4& blk, const SimdWatertightRay& sw, float tmax, __m128& t_out, __m128& e1_out,
                     __m128& e2_out, __m128& inv_det_out) {
  const WatertightRay& w = sw.w;
  const __m128 ox = sw.ox, oy = sw.oy, oz = sw.oz, sx = sw.sx, sy = sw.sy, sz = sw.sz;
  __m128 az = _mm_sub_ps(_mm_load_ps(blk.v[0][w.kz]), oz);
  __m128 bz = _mm_sub_ps(_mm_load_ps(blk.v[1][w.kz]), oz);
  __m128 cz = _mm_sub_ps(_mm_load_ps(blk.v[2][w.kz]), oz);
  const __m128 ax = _mm_add_ps(_mm_sub_ps(_mm_load_ps(blk.v[0][w.kx]), ox), _mm_mul_ps(sx, az));
  const __m128 ay = _mm_add_ps(_mm_sub_ps(_mm_load_ps(blk.v[0][w.ky]), oy), _mm_mul_ps(sy, az));
  const __m128 bx = _mm_add_ps(_mm_sub_ps(_mm_load_ps(blk.v[1][w.kx]), ox), _mm_mul_ps(sx, bz));
  const __m128 by = _mm_add_ps(_mm_sub_ps(_mm_load_ps(blk.v[1][w.ky]), oy), _mm_mul_ps(sy, bz));
  const __m128 cx = _mm_add_ps(_mm_sub_ps(_mm_load_ps(blk.v[2][w.kx]), ox), _mm_mul_ps(sx, cz));
  const __m128 cy = _mm_add_ps(_mm_sub_ps(_mm_load_ps(blk.v[2][w.ky]), oy), _mm_mul_ps(sy, cz));
  __m128 e0 = _mm_sub_ps(_mm_mul_ps(bx, cy), _mm_mul_ps(by, cx));
  __m128 e1 = _mm_sub_ps(_mm_mul_ps(cx, ay), _mm_mul_ps(cy, ax));
  __m128 e2 = _mm_sub_ps(_mm_mul_ps(ax, by), _mm_mul_ps(ay, bx));
  const __m128 zero = _mm_setzero_ps();
  const __m128i prims = _mm_load_si128(reinterpret_cast<const __m128i*>(blk.prim));
  const __m128 valid = _mm_castsi128_ps(_mm_xor_si128(_mm_cmpeq_epi32(prims, _mm_set1_epi32(-1)), _mm_set1_epi32(-1)));
  const __m128 on_edge = _mm_and_ps(
      valid, _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)), _mm_cmpeq_ps(e2, zero)));
  if (_mm_movemask_ps(on_edge)) {
    // Exactly zero edge functions are re-evaluated in double so shared edges are decided consistently.
    alignas(16) float fax[4], fay[4], fbx[4], fby[4], fcx[4], fcy[4], f0[4], f1[4], f2[4];
    _mm_store_ps(fax, ax); _mm_store_ps(fay, ay); _mm_store_ps(fbx, bx); _mm_store_ps(fby, by);
    _mm_store_ps(fcx, cx); _mm_store_ps(fcy, cy);
    _mm_store_ps(f0, e0); _mm_store_ps(f1, e1); _mm_store_ps(f2, e2);
    const int m = _mm_movemask_ps(on_edge);
    for (int i = 0; i < 4; ++i) {
      if (!(m >> i & 1)) continue;
      f0[i] = float(double(fbx[i]) * double(fcy[i]) - double(fby[i]) * double(fcx[i]));
      f1[i] = float(double(fcx[i]) * double(fay[i]) - double(fcy[i]) * double(fax[i]));
      f2[i] = float(double(fax[i]) * double(fby[i]) - double(fay[i]) * double(fbx[i]));
    }
    e0 = _mm_load_ps(f0); e1 = _mm_load_ps(f1); e2 = _mm_load_ps(f2);
  }
  const __m128 neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)), _mm_cmplt_ps(e2, zero));
  const __m128 pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)), _mm_cmpgt_ps(e2, zero));
  const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
  __m128 ok = _mm_andnot_ps(_mm_and_ps(neg, pos), _mm_and_ps(valid, _mm_cmpneq_ps(det, zero)));
  if (!_mm_movemask_ps(ok)) return 0;
  az = _mm_mul_ps(az, sz);
  bz = _mm_mul_ps(bz, sz);
  cz = _mm_mul_ps(cz, sz);
  const __m128 t_scaled = _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, az), _mm_mul_ps(e1, bz)), _mm_mul_ps(e2, cz));
  // With the sign of det folded into both sides: 0 < t_scaled and t_scaled <= tmax * det.
  const __m128 sign_mask = _mm_set1_ps(-0.0f);
  const __m128 det_sign = _mm_and_ps(det, sign_mask);
  const __m128 ts = _mm_xor_ps(t_scaled, det_sign), abs_det = _mm_xor_ps(det, det_sign);
  const __m128 vtmax = _mm_set1_ps(tmax);
  ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpgt_ps(ts, zero), _mm_cmple_ps(ts, _mm_mul_ps(vtmax, abs_det))));
  if (!_mm_movemask_ps(ok)) return 0;
  const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
  const __m128 t = _mm_mul_ps(t_scaled, inv_det);
  ok = _mm_and_ps(ok, _mm_cmplt_ps(t, vtmax));
  // Conservative check that t is really positive (pbrt-v4 section 6.8.4): reject hits within rounding of 0.
  auto abs = [&](__m128 x) { return _mm_andnot_ps(sign_mask, x); };
  auto max3 = [&](__m128 x, __m128 y, __m128 z) { return _mm_max_ps(_mm_max_ps(abs(x), abs(y)), abs(z)); };
  const __m128 max_zt = max3(az, bz, cz), max_xt = max3(ax, bx, cx), max_yt = max3(ay, by, cy);
  const __m128 delta_z = _mm_mul_ps(_mm_set1_ps(gamma_bound(3)), max_zt);
  const __m128 g5 = _mm_set1_ps(gamma_bound(5));
  const __m128 delta_x = _mm_mul_ps(g5, _mm_add_ps(max_xt, max_zt));
  const __m128 delta_y = _mm_mul_ps(g5, _mm_add_ps(max_yt, max_zt));
  const __m128 delta_e = _mm_mul_ps(
      _mm_set1_ps(2.0f),
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(gamma_bound(2)), max_xt), max_yt),
                            _mm_mul_ps(delta_y, max_xt)),
                 _mm_mul_ps(delta_x, max_yt)));
  const __m128 max_e = max3(e0, e1, e2);
  const __m128 delta_t = _mm_mul_ps(
      _mm_mul_ps(_mm_set1_ps(3.0f),
                 _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(gamma_bound(3)), max_e), max_zt),
                                       _mm_mul_ps(delta_e, max_zt)),
                            _mm_mul_ps(delta_z, max_e))),
      abs(inv_det));
  const __m128 certain = _mm_cmpgt_ps(t, delta_t);
  const int unsure = _mm_movemask_ps(_mm_andnot_ps(certain, ok));
  int mask = _mm_movemask_ps(_mm_and_ps(ok, certain));
  t_out = t;
  if (unsure) {  // rare: hits within rounding of the origin are decided in double, as in intersect_triangle
    alignas(16) float tt[4], dt[4], fd[4];
    _mm_store_ps(tt, t);
    _mm_store_ps(dt, delta_t);
    _mm_store_ps(fd, det);
    for (int i = 0; i < 4; ++i) {
      if (!(unsure >> i & 1)) continue;
      auto vertex = [&](int k) { return vec3(blk.v[k][0][i], blk.v[k][1][i], blk.v[k][2][i]); };
      if (small_t_is_positive(w, vertex(0), vertex(1), vertex(2), dt[i], fd[i])) {
        tt[i] = std::max(tt[i], std::numeric_limits<float>::denorm_min());
        mask |= 1 << i;
      }
    }
    t_out = _mm_load_ps(tt);
  }
  e1_out = e1;
  e2_out = e2;
  inv_det_out = inv_det;
  return mask;
}

PT_INLINE Tri4Hit closest_in_block(const Tri4& blk, const SimdWatertightRay& w, float tmax) {
  __m128 t, e1, e2, inv_det;
  const int mask = tri4_test(blk, w, tmax, t, e1, e2, inv_det);
  Tri4Hit hit;
  if (!mask) return hit;
  alignas(16) float ft[4], f1[4], f2[4], fi[4];
  _mm_store_ps(ft, t);
  for (int i = 0; i < 4; ++i)
    if ((mask >> i & 1) && ft[i] < hit.t) hit.t = ft[i], hit.lane = i;  // ties: the lowest lane, as a scalar loop
  _mm_store_ps(f1, e1);
  _mm_store_ps(f2, e2);
  _mm_store_ps(fi, inv_det);
  hit.b1 = f1[hit.lane] * fi[hit.lane];
  hit.b2 = f2[hit.lane] * fi[hit.lane];
  return hit;
}

/// Ordered traversal. The stack holds (child, entry distance) pairs; children of a node are pushed far to near so
/// the nearest is visited first, and popped entries beyond the current closest hit are dropped. Children about to
/// be visited later are prefetched: on large trees incoherent rays mostly wait for memory.
template <bool kAnyHit>
bool traverse(const Bvh8& bvh, const Ray& ray, float* t_hit, uint32_t* prim, float* b1, float* b2,
              const float** vertices) {
  if (bvh.empty()) return false;
  const SimdNodeRay nr(make_node_ray(ray));
  const WatertightRay w = make_watertight_ray(ray);
  const SimdWatertightRay wr(w);
  struct Entry {
    ChildRef ref;
    float t;
  };
  Entry stack[7 * kBvhMaxDepth + 8];
  int top = 0;
  bool found = false;
  // The closest hit so far lives in locals: written through the pointers, which may alias ray.tmax, the compiler
  // would reload tmax after every hit. pop_tmax is the bound popped entries are checked against.
  float tmax = ray.tmax, pop_tmax = tmax * kRobust, hit_b1 = 0.0f, hit_b2 = 0.0f;
  // The hit triangle's lane of its block, &v[0][0][lane]: its prim id is lane_prim(hit_lane), so one register holds
  // both.
  const float* hit_lane = nullptr;
  ChildRef cur = 0;
  for (;;) {
    while (!is_leaf_ref(cur)) {
      const Bvh8Node& node = bvh.node(cur);
      alignas(32) float tnear[8];
      uint32_t mask = node_test_simd(node, nr, tmax, tnear);
      if (mask == 0) goto pop;
      int first = std::countr_zero(mask);
      mask &= mask - 1;
      if (mask == 0) {  // one child hit: no stack traffic
        cur = node.child[first];
        continue;
      }
      if constexpr (!kAnyHit) {
        const int second = std::countr_zero(mask);
        if ((mask & (mask - 1)) == 0) {  // two children hit, the most common case: push the farther one
          const bool swap = tnear[second] < tnear[first];
          const int near = swap ? second : first, far = swap ? first : second;
          stack[top++] = {node.child[far], tnear[far]};
          prefetch_child(bvh, node.child[far]);
          cur = node.child[near];
          continue;
        }
      }
      if constexpr (kAnyHit) {  // shadow rays take children in slot order: measured faster than near-first
        cur = node.child[first];
        do {
          const int i = std::countr_zero(mask);
          stack[top++] = {node.child[i], tnear[i]};
          prefetch_child(bvh, node.child[i]);
          mask &= mask - 1;
        } while (mask);
        continue;
      } else {
        // Push all hit children, then insertion-sort the new entries by decreasing distance: nearest on top.
        const int base = top;
        stack[top++] = {node.child[first], tnear[first]};
        do {
          const int i = std::countr_zero(mask);
          Entry e{node.child[i], tnear[i]};
          prefetch_child(bvh, e.ref);
          int j = top++;
          while (j > base && stack[j - 1].t < e.t) {
            stack[j] = stack[j - 1];
            --j;
          }
          stack[j] = e;
          mask &= mask - 1;
        } while (mask);
        cur = stack[--top].ref;
        continue;
      }
    }
    // A leaf: ceil(n / 4) blocks. An unused slot's empty box is entered when every distance of the node test is
    // NaN (coordinates near 1e30 times a large 1/dir overflow to inf, and inf - inf leaves the interval open).
    if (cur == kEmptyChild) goto pop;
    {
      const uint32_t first_block = leaf_first(cur), end_block = first_block + leaf_count(cur) * kBlockUnits;
      for (uint32_t k = first_block; k < end_block; k += kBlockUnits) {
        const Tri4& blk = bvh.block(k);
        if constexpr (kAnyHit) {
          __m128 t, e1, e2, inv_det;
          if (tri4_test(blk, wr, tmax, t, e1, e2, inv_det)) return true;
        } else {
          const Tri4Hit h = closest_in_block(blk, wr, tmax);
          if (h.lane >= 0) {
            tmax = h.t;
            pop_tmax = tmax * kRobust;
            hit_lane = &blk.v[0][0][h.lane];
            hit_b1 = h.b1;
            hit_b2 = h.b2;
            found = true;
          }
        }
      }
    }
  pop:
    for (;;) {
      if (top == 0) {
        if constexpr (!kAnyHit) {
          if (found) *t_hit = tmax, *prim = lane_prim(hit_lane), *b1 = hit_b1, *b2 = hit_b2;
          if (found && vertices) *vertices = hit_lane;
        }
        return found;
      }
      const Entry e = stack[--top];
      if (kAnyHit || e.t <= pop_tmax) {  // tnear may be rounded up a little
        cur = e.ref;
        break;
      }
    }
  }
}

}  // namespace

uint32_t intersect_node8_scalar(const Bvh8Node& node, const NodeRay& ray, float tmax, float tnear[8]) {
  return node_test_scalar(node, ray, tmax, tnear);
}
uint32_t intersect_node8(const Bvh8Node& node, const NodeRay& ray, float tmax, float tnear[8]) {
  return node_test_simd(node, SimdNodeRay(ray), tmax, tnear);
}
const char* bvh8_simd_name() { return kSimdName; }

Tri4Hit intersect_tri4(const Tri4& block, const WatertightRay& ray, float tmax) {
  return closest_in_block(block, SimdWatertightRay(ray), tmax);
}
bool occluded_tri4(const Tri4& block, const WatertightRay& ray, float tmax) {
  __m128 t, e1, e2, inv_det;
  return tri4_test(block, SimdWatertightRay(ray), tmax, t, e1, e2, inv_det) != 0;
}

bool intersect_bvh8(const Bvh8& bvh, Ray& ray, uint32_t& prim, float& b1, float& b2, const float** vertices) {
  return traverse<false>(bvh, ray, &ray.tmax, &prim, &b1, &b2, vertices);
}
bool occluded_bvh8(const Bvh8& bvh, const Ray& ray) {
  // No copy of the ray: reading a just-written Ray back as 16-byte words stalls store forwarding (1% of a
  // cornell36 frame in this function alone).
  return traverse<true>(bvh, ray, nullptr, nullptr, nullptr, nullptr, nullptr);
}

}  // namespace pt
