#include "render/emissive_pairs.h"

#include <algorithm>
#include <bit>

#include "core/huge_page_allocator.h"
#include "core/radix_sort.h"
#include "core/rng.h"

namespace pt {

bool parallelogram_of(const vec3* a, const vec3* b, vec3& corner, vec3& e1, vec3& e2) {
  // A triangle with a repeated corner has no area to share, and would let one corner of the other match twice
  // below (the unshared corner's index 3 - i - j then reads past the triangle).
  auto repeats = [](const vec3* v) { return v[0] == v[1] || v[1] == v[2] || v[2] == v[0]; };
  if (repeats(a) || repeats(b)) return false;
  int shared_a[2], shared_b[2], n = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j] && n < 2) {
        shared_a[n] = i;
        shared_b[n] = j;
        ++n;
      }
  if (n != 2) return false;
  const vec3 ua = a[3 - shared_a[0] - shared_a[1]], ub = b[3 - shared_b[0] - shared_b[1]];
  const vec3 s0 = a[shared_a[0]], s1 = a[shared_a[1]];
  const vec3 na = glm::cross(a[1] - a[0], a[2] - a[0]), nb = glm::cross(b[1] - b[0], b[2] - b[0]);
  if (!(glm::dot(na, nb) > 0.0f)) return false;
  const float scale =
      max_component(glm::abs(ua - s0)) + max_component(glm::abs(ub - s0)) + max_component(glm::abs(s1 - s0));
  if (!(max_component(glm::abs((ua + ub) - (s0 + s1))) <= 1e-6f * scale)) return false;
  corner = s0;
  e1 = ua - s0;
  e2 = ub - s0;
  if (glm::dot(glm::cross(e1, e2), na) < 0.0f) std::swap(e1, e2);
  return true;
}

namespace {

constexpr size_t kMaxTrianglesOnAnEdge = 4;

/// A hash of a corner. The coordinates' bits are those of x + 0, so -0 and +0 (equal to parallelogram_of's ==)
/// hash alike; unequal corners may collide, and the pairs found are checked by parallelogram_of.
uint64_t corner_hash(vec3 v) {
  const uint64_t x = std::bit_cast<uint32_t>(v.x + 0.0f), y = std::bit_cast<uint32_t>(v.y + 0.0f),
                 z = std::bit_cast<uint32_t>(v.z + 0.0f);
  return mix_bits((x | y << 32) ^ mix_bits(z));
}

/// A 32-bit hash of the edge between corners of hashes a and b, whichever end comes first.
uint32_t edge_hash(uint64_t a, uint64_t b) { return uint32_t(mix_bits(std::min(a, b) + 3 * std::max(a, b)) >> 32); }

}  // namespace

std::vector<int32_t> pair_parallelograms(std::span<const vec3> corners, std::span<const uint32_t> material,
                                         std::span<const uint8_t> candidate) {
  const uint32_t count = uint32_t(candidate.size());
  std::vector<int32_t> partner(count, -1);
  auto tri = [&](uint32_t t) { return &corners[3 * size_t(t)]; };
  auto link = [&](uint32_t t, uint32_t u) {
    partner[t] = int32_t(u);
    partner[u] = int32_t(t);
  };
  // Candidate pairs by kind, each as t << 32 | u (t < u): sorted, that is the mesh's order.
  HugeVector<uint64_t> rect_apart, sheared_near, sheared_apart;
  auto key = [](uint32_t t, uint32_t u) { return uint64_t(t) << 32 | u; };
  // Neighbours in the mesh that form a rectangle come first in the order below, so they can be taken at once, and
  // the search across edges is left with the rest: in most files, nothing.
  for (uint32_t t = 0; t + 1 < count; ++t) {
    vec3 corner, e1, e2;
    if (partner[t] < 0 && candidate[t] && candidate[t + 1] && material[t] == material[t + 1] &&
        parallelogram_of(tri(t), tri(t + 1), corner, e1, e2)) {
      if (at_right_angle(e1, e2))
        link(t, t + 1);
      else
        sheared_near.push_back(key(t, t + 1));
    }
  }
  auto single = [&](uint32_t t) { return candidate[t] && partner[t] < 0; };
  // Pairs apart, by the edges their triangles share: a 32-bit hash of the edge above its triangle, sorted stably
  // by the hash, so each edge's triangles are together and in the mesh's order.
  size_t singles = 0;
  for (uint32_t t = 0; t < count; ++t) singles += single(t);
  if (singles < 2) return partner;
  HugeVector<uint64_t> edges;  // fresh pages cost more than the hashing on this project's VMs (huge_page_allocator.h)
  edges.reserve(3 * singles);
  for (uint32_t t = 0; t < count; ++t)
    if (single(t)) {
      const uint64_t h[3] = {corner_hash(tri(t)[0]), corner_hash(tri(t)[1]), corner_hash(tri(t)[2])};
      for (int k = 0; k < 3; ++k) edges.push_back(uint64_t(edge_hash(h[k], h[(k + 1) % 3])) << 32 | t);
    }
  radix_sort(edges, 32);
  rect_apart.reserve(edges.size() / 3);  // a triangle pairs across one of its edges, mostly
  sheared_apart.reserve(edges.size() / 3);
  for (size_t i = 0; i < edges.size();) {
    size_t end = i + 1;
    while (end < edges.size() && edges[end] >> 32 == edges[i] >> 32) ++end;
    if (end - i <= kMaxTrianglesOnAnEdge)
      for (size_t a = i; a < end; ++a)
        for (size_t b = a + 1; b < end; ++b) {
          const uint32_t t = uint32_t(edges[a]), u = uint32_t(edges[b]);  // t <= u
          vec3 corner, e1, e2;
          if (u > t + 1 && material[t] == material[u] && parallelogram_of(tri(t), tri(u), corner, e1, e2))
            (at_right_angle(e1, e2) ? rect_apart : sheared_apart).push_back(key(t, u));
        }
    i = end;
  }
  // Rectangles first (those apart now), then neighbours in the mesh, then pairs apart, each in the mesh's order:
  // greedy, so deterministic.
  radix_sort(rect_apart);
  radix_sort(sheared_apart);
  for (const HugeVector<uint64_t>* kind : {&rect_apart, &sheared_near, &sheared_apart})
    for (uint64_t k : *kind) {
      const uint32_t t = uint32_t(k >> 32), u = uint32_t(k);
      if (partner[t] < 0 && partner[u] < 0) link(t, u);
    }
  return partner;
}

}  // namespace pt
