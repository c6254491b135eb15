#pragma once
/// Meshes generated in code: the large mesh of the built-in scenes, so no large model has to ship with the
/// repository (scene JSON extension: a mesh shape's "generate": {"kind": "torus-knot", ...}).
#include <cstdint>

#include "scene/scene.h"

namespace pt {

/// A (p, q) torus knot swept by a circle: the tube around the curve
///   c(t) = (r(t) cos pt, r(t) sin pt, (radius / 3) sin qt),  r(t) = (radius / 3) (2 + cos qt),  t in [0, 2 pi),
/// which winds p times around the z axis and q times through the hole. It is a knot when p and q are coprime.
struct TorusKnotParams {
  int p = 2;
  int q = 3;
  int segments = 800;   ///< rings along the curve (>= 3)
  int sides = 64;       ///< vertices around each ring (>= 3)
  float radius = 1.0f;  ///< overall radius of the knot, before adding the tube
  float tube = 0.12f;   ///< radius of the swept circle
};

/// The tube as a closed, consistently wound mesh with 2 * segments * sides triangles, fronts facing outward
/// (counter-clockwise seen from outside), exact shading normals (the ring's radial direction: each ring lies in
/// the curve's normal plane, so that direction is perpendicular to both surface tangents), and every triangle set
/// to `material`. The ring frame is (T, N, B) with N the component of the direction away from the z axis that is
/// perpendicular to T: it depends only on the point of the curve, so the rings close up without a seam. Vertices
/// are stored ring by ring (vertex j of ring i at i * sides + j), each with its own normal. Requires
/// p >= 1 (then T is never radial), segments, sides >= 3, radius, tube > 0.
Mesh make_torus_knot(const TorusKnotParams& params, uint32_t material = 0);

/// Signed volume enclosed by a closed triangle mesh, by the divergence theorem (sum of signed tetrahedra to the
/// origin): positive when every front faces outward.
double signed_volume(const Mesh& mesh);

}  // namespace pt
