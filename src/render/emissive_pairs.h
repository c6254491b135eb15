#pragma once
/// Which emissive triangles of a scene's meshes become one parallelogram light (issue 11: "two coplanar emissive
/// triangles of one material that share an edge and form a parallelogram are merged into one parallelogram light").
/// One light in place of two halves the light count and lets a rectangle be sampled by solid angle as a whole.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace pt {

/// Whether triangles a and b (three distinct corners each) share an edge exactly (two equal corners), face the same way
/// and together form a parallelogram (their unshared corners' midpoint is the shared edge's, to a relative 1e-6): then
/// corner, e1 and e2 describe it, oriented like the triangles, so the light is the triangles' surface and light_pdf
/// matches hits on either one.
bool parallelogram_of(const vec3* a, const vec3* b, vec3& corner, vec3& e1, vec3& e2);

/// Pairs triangles into parallelograms: partner[t] = u and partner[u] = t for a pair, -1 for a triangle left alone.
/// Only triangles with `candidate[t]` set pair, and only with one of the same `material` (both spans, like
/// `corners` with three per triangle, cover at least candidate.size() triangles). Any two triangles across an edge
/// may pair (exporters and mesh optimisers reorder triangles), chosen greedily: rectangles before sheared
/// parallelograms, so a shuffled grid of quads pairs back into its quads rather than across them; then neighbours in
/// the mesh's order (an OBJ quad is a fan of two, and most exporters write a quad's halves together; these were the
/// only pairs made before pairs apart were looked for), before pairs apart; each in the mesh's order. Deterministic:
/// the result depends on the triangles and their order only. An edge shared by more than four candidates (non-manifold;
/// a degenerate mesh could put every triangle on one edge) pairs nothing across it unless they are neighbours in the
/// mesh, so the work stays linear in the triangles after a sort.
std::vector<int32_t> pair_parallelograms(std::span<const vec3> corners, std::span<const uint32_t> material,
                                         std::span<const uint8_t> candidate);

}  // namespace pt
