#include "scene/transform.h"

namespace pt {

glm::dmat3 rotation_matrix(vec3 axis, float degrees) {
  dvec3 k = glm::normalize(dvec3(axis));
  double a = glm::radians(double(degrees)), s = std::sin(a), c = std::cos(a);
  // Cross-product matrix of k, column by column (GLM is column-major): K v = k x v.
  glm::dmat3 K(0.0, k.z, -k.y, -k.z, 0.0, k.x, k.y, -k.x, 0.0);
  return glm::dmat3(1.0) + s * K + (1.0 - c) * (K * K);
}

Transform make_transform(vec3 scale, vec3 axis, float degrees, vec3 translation) {
  Transform t;
  glm::dmat3 s(scale.x, 0.0, 0.0, 0.0, scale.y, 0.0, 0.0, 0.0, scale.z);
  t.linear = rotation_matrix(axis, degrees) * s;
  t.translation = dvec3(translation);
  return t;
}

void apply_transform(Mesh& mesh, const Transform& t) {
  mesh.origin = t.linear * mesh.origin + t.translation;
  for (vec3& p : mesh.positions) p = vec3(t.linear * dvec3(p));
  glm::dmat3 normal_matrix = glm::transpose(glm::inverse(t.linear));
  for (vec3& n : mesh.normals) {
    vec3 m = vec3(normal_matrix * dvec3(n));
    float len = glm::length(m);
    n = len > 0.0f && std::isfinite(len) ? m / len : vec3(0.0f);
  }
  if (glm::determinant(t.linear) < 0.0) {
    for (uvec3& tri : mesh.indices) std::swap(tri.y, tri.z);
    for (uvec3& tri : mesh.normal_indices) std::swap(tri.y, tri.z);
  }
}

}  // namespace pt
