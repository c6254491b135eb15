#include "scene/procedural.h"

namespace pt {

namespace {

dvec3 knot_point(const TorusKnotParams& k, double t) {
  double r = (2.0 + std::cos(k.q * t)) * k.radius / 3.0;
  return {r * std::cos(k.p * t), r * std::sin(k.p * t), std::sin(k.q * t) * k.radius / 3.0};
}

}  // namespace

Mesh make_torus_knot(const TorusKnotParams& k) {
  Mesh mesh;
  mesh.name = "torus-knot";
  const int n = k.segments, m = k.sides;
  mesh.positions.reserve(size_t(n) * size_t(m));
  mesh.normals.reserve(size_t(n) * size_t(m));
  const double two_pi = 2.0 * 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    double t = two_pi * i / n, dt = two_pi / n * 0.25;
    dvec3 c = knot_point(k, t);
    dvec3 tangent = glm::normalize(knot_point(k, t + dt) - knot_point(k, t - dt));
    // The direction away from the knot's symmetry axis is never parallel to the tangent of a torus knot.
    dvec3 out = glm::normalize(dvec3(c.x, c.y, 0.0));
    dvec3 b = glm::normalize(glm::cross(tangent, out));
    dvec3 nrm = glm::cross(b, tangent);
    for (int j = 0; j < m; ++j) {
      double phi = two_pi * j / m;
      dvec3 dir = std::cos(phi) * nrm + std::sin(phi) * b;
      mesh.positions.push_back(vec3(c + double(k.tube) * dir));
      mesh.normals.push_back(vec3(dir));
    }
  }
  auto id = [&](int i, int j) { return uint32_t(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      mesh.indices.push_back({a, b, c});
      mesh.indices.push_back({a, c, d});
    }
  if (signed_volume(mesh) < 0.0)
    for (uvec3& t : mesh.indices) std::swap(t.y, t.z);
  mesh.normal_indices = mesh.indices;
  return mesh;
}

double signed_volume(const Mesh& mesh) {
  double v = 0.0;
  for (uvec3 t : mesh.indices) {
    dvec3 a(mesh.positions[t.x]), b(mesh.positions[t.y]), c(mesh.positions[t.z]);
    v += glm::dot(a, glm::cross(b, c));
  }
  return v / 6.0;
}

}  // namespace pt
