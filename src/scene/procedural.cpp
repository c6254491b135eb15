#include "scene/procedural.h"

namespace pt {

namespace {

/// The knot curve and its derivative at t.
void knot_curve(const TorusKnotParams& k, double t, dvec3& point, dvec3& derivative) {
  const double s = double(k.radius) / 3.0, p = k.p, q = k.q;
  double r = s * (2.0 + std::cos(q * t)), dr = -s * q * std::sin(q * t);
  point = {r * std::cos(p * t), r * std::sin(p * t), s * std::sin(q * t)};
  derivative = {dr * std::cos(p * t) - r * p * std::sin(p * t), dr * std::sin(p * t) + r * p * std::cos(p * t),
                s * q * std::cos(q * t)};
}

}  // namespace

Mesh make_torus_knot(const TorusKnotParams& k, uint32_t material) {
  Mesh mesh;
  mesh.name = "torus-knot";
  const uint32_t n = uint32_t(std::max(k.segments, 3)), m = uint32_t(std::max(k.sides, 3));
  mesh.positions.reserve(size_t(n) * m);
  mesh.normals.reserve(size_t(n) * m);
  const double two_pi = 6.283185307179586476925;
  for (uint32_t i = 0; i < n; ++i) {
    dvec3 c, dc;
    knot_curve(k, two_pi * i / n, c, dc);
    dvec3 tangent = glm::normalize(dc);
    dvec3 away(c.x, c.y, 0.0);  // r(t) >= radius / 3 > 0: never on the axis
    dvec3 normal = glm::normalize(away - glm::dot(away, tangent) * tangent);
    dvec3 binormal = glm::cross(tangent, normal);
    for (uint32_t j = 0; j < m; ++j) {
      double phi = two_pi * j / m;
      dvec3 dir = std::cos(phi) * normal + std::sin(phi) * binormal;
      mesh.positions.push_back(vec3(c + double(k.tube) * dir));
      mesh.normals.push_back(vec3(dir));
    }
  }
  // With S(t, phi) = c(t) + tube (cos phi N + sin phi B): dS/dphi x dS/dt points along +dir (outward), because
  // (T, N, B) is right-handed. So the corners go around each quad in the order (t, phi), (t, phi+1), (t+1, phi+1).
  auto id = [&](uint32_t i, uint32_t j) { return (i % n) * m + j % m; };
  mesh.indices.reserve(2 * size_t(n) * m);
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < m; ++j) {
      uint32_t a = id(i, j), b = id(i, j + 1), c = id(i + 1, j + 1), d = id(i + 1, j);
      mesh.indices.push_back({a, b, c});
      mesh.indices.push_back({a, c, d});
    }
  mesh.normal_indices = mesh.indices;
  mesh.materials.assign(mesh.indices.size(), material);
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
