#include "scene/transform.h"

namespace pt {

mat3 rotation_matrix(vec3 axis, float degrees) {
  vec3 k = glm::normalize(axis);
  float a = glm::radians(degrees), s = std::sin(a), c = std::cos(a);
  // Cross-product matrix of k, column by column (GLM is column-major): K v = k x v.
  mat3 K(0.0f, k.z, -k.y, -k.z, 0.0f, k.x, k.y, -k.x, 0.0f);
  return mat3(1.0f) + s * K + (1.0f - c) * (K * K);
}

Transform make_transform(vec3 scale, vec3 axis, float degrees, vec3 translation) {
  Transform t;
  mat3 s(scale.x, 0.0f, 0.0f, 0.0f, scale.y, 0.0f, 0.0f, 0.0f, scale.z);
  t.linear = rotation_matrix(axis, degrees) * s;
  t.translation = translation;
  return t;
}

void apply_transform(Mesh& mesh, const Transform& t) {
  for (vec3& p : mesh.positions) p = t.linear * p + t.translation;
  mat3 normal_matrix = glm::transpose(glm::inverse(t.linear));
  for (vec3& n : mesh.normals) {
    vec3 m = normal_matrix * n;
    float len = glm::length(m);
    n = len > 0.0f && std::isfinite(len) ? m / len : vec3(0.0f);
  }
  if (glm::determinant(t.linear) < 0.0f) {
    for (uvec3& tri : mesh.indices) std::swap(tri.y, tri.z);
    for (uvec3& tri : mesh.normal_indices) std::swap(tri.y, tri.z);
  }
}

}  // namespace pt
