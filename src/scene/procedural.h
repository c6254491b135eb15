#pragma once
/// Meshes generated in code: the large mesh of the built-in scenes (no large model ships with the repository).
#include "scene/scene.h"

namespace pt {

/// A (p, q) torus knot tube: the curve ((2 + cos q t) cos p t, (2 + cos q t) sin p t, sin q t) * radius / 3 swept
/// by a circle of radius `tube`. Closed, consistently wound with fronts facing outward, 2 * segments * sides
/// triangles. Materials are left empty (the caller assigns them).
struct TorusKnotParams {
  int p = 2;
  int q = 3;
  int segments = 800;
  int sides = 64;
  float radius = 1.0f;
  float tube = 0.12f;
};
Mesh make_torus_knot(const TorusKnotParams& params);

/// Signed volume enclosed by a closed mesh (positive when fronts face outward): divergence theorem.
double signed_volume(const Mesh& mesh);

}  // namespace pt
