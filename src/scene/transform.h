#pragma once
/// The affine transforms of JSON mesh shapes: scale, then rotate about an axis, then translate.
#include "core/math.h"
#include "scene/scene.h"

namespace pt {

/// x -> linear * x + translation, in double (see apply_transform).
struct Transform {
  glm::dmat3 linear{1.0};
  dvec3 translation{0.0};
};

/// Rotation by `degrees` about `axis` (any non-zero length), counter-clockwise when the axis points at the viewer
/// (right-hand rule): Rodrigues' formula, R = I + sin(a) K + (1 - cos(a)) K^2 with K the cross-product matrix of
/// the unit axis (pbrt-v4, section 3.9.6).
glm::dmat3 rotation_matrix(vec3 axis, float degrees);

/// translate(t) * rotate(axis, degrees) * scale(s): the scene JSON's order (scale first).
Transform make_transform(vec3 scale, vec3 axis, float degrees, vec3 translation);

/// Moves a mesh into world space: its origin by the affine map and its positions (relative to the origin) by the
/// linear part, both in double, so a translation never rounds the positions to the coarse float grid far from the
/// world origin (Mesh::origin); shading normals by the inverse transpose of the linear part (pbrt-v4, section
/// 3.10.3), renormalized. A mirroring map (negative determinant) turns
/// counter-clockwise triangles clockwise, so two corners of every triangle are swapped to keep the front side on
/// the same side of the surface as before.
void apply_transform(Mesh& mesh, const Transform& t);

}  // namespace pt
