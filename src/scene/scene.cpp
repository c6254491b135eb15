#include "scene/scene.h"

#include <cmath>

#include "scene/load_internal.h"

namespace pt {

namespace {

/// Irradiance per unit radiance at distance h below the center of a w x d rectangle facing it: four corner
/// rectangles of the differential-area-to-rectangle form factor (Howell, "A Catalog of Radiation Heat Transfer
/// Configuration Factors", B-3), E / L = pi * F. Tends to w d / h^2 for a small rectangle and to pi for a huge one.
double irradiance_per_radiance(double w, double d, double h) {
  double x = 0.5 * w / h, y = 0.5 * d / h;
  double sx = std::sqrt(1.0 + x * x), sy = std::sqrt(1.0 + y * y);
  return 2.0 * (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy));
}

/// Adds a downward-facing rectangle light centred above `b`: at height hi.y + half the largest extent, half as
/// wide as the bounds in x and z (at least a quarter of the largest extent, so flat bounds still get a light), and
/// bright enough for an irradiance of 2 at the center of the bounds' top.
void add_default_light(Scene& scene, const AABB& b) {
  vec3 extent = b.extent();
  float largest = max_component(extent) > 0.0f ? max_component(extent) : 1.0f;
  float h = 0.5f * largest;
  float w = std::max(0.5f * extent.x, 0.25f * largest), d = std::max(0.5f * extent.z, 0.25f * largest);
  Material light;
  light.name = "default-light";
  light.albedo = vec3(0.0f);
  light.emission = vec3(float(2.0 / irradiance_per_radiance(w, d, h)));
  vec3 c = b.center();
  Quad q;
  q.corner = vec3(c.x - 0.5f * w, b.hi.y + h, c.z - 0.5f * d);
  q.edge1 = vec3(w, 0.0f, 0.0f);
  q.edge2 = vec3(0.0f, 0.0f, d);  // cross(edge1, edge2) = -y: the front faces down
  q.material = add_material(scene, light);
  scene.quads.push_back(q);
  scene.warnings.push_back(scene.source + ": no light in the scene: added a default rectangle light above it");
}

bool usable(const AABB& b) { return !b.empty() && is_finite(b.lo) && is_finite(b.hi); }

}  // namespace

AABB Scene::bounds() const {
  AABB b;
  for (const Mesh& m : meshes)
    for (uvec3 t : m.indices)
      for (int k = 0; k < 3; ++k) b.extend(m.positions[t[k]]);
  for (const Sphere& s : spheres) {
    b.extend(s.center - vec3(s.radius));
    b.extend(s.center + vec3(s.radius));
  }
  for (const Quad& q : quads) {
    b.extend(q.corner);
    b.extend(q.corner + q.edge1);
    b.extend(q.corner + q.edge2);
    b.extend(q.corner + q.edge1 + q.edge2);
  }
  return b;
}

bool Scene::has_emitter() const {
  auto emits = [&](uint32_t m) { return m < materials.size() && materials[m].emissive(); };
  for (const Mesh& mesh : meshes)
    for (uint32_t m : mesh.materials)
      if (emits(m)) return true;
  for (const Sphere& s : spheres)
    if (emits(s.material)) return true;
  for (const Quad& q : quads)
    if (emits(q.material)) return true;
  return false;
}

Camera framing_camera(const AABB& bounds) {
  Camera cam;
  if (!usable(bounds)) return cam;
  float radius = 0.5f * glm::length(bounds.extent());
  if (!(radius > 0.0f) || !std::isfinite(radius)) radius = 1.0f;  // a single point
  // Far from the origin, keep the eye a few thousand float steps from the target so the view direction exists.
  radius = std::max(radius, 1e-5f * max_component(glm::abs(bounds.center())));
  cam.fov_deg = 40.0f;
  float distance = 1.1f * radius / std::sin(glm::radians(0.5f * cam.fov_deg));
  cam.target = bounds.center();
  cam.eye = cam.target + vec3(0.0f, 0.0f, distance);
  cam.up = vec3(0.0f, 1.0f, 0.0f);
  return cam;
}

std::string select_camera(Scene& scene, size_t index) {
  if (index >= scene.cameras.size())
    return "camera " + std::to_string(index) + " out of range (" + scene.source + " defines " +
           std::to_string(scene.cameras.size()) + " perspective camera" + (scene.cameras.size() == 1 ? "" : "s") + ")";
  scene.camera = scene.cameras[index];
  return "";
}

void finalize_scene(Scene& scene) {
  AABB b = scene.bounds();
  if (!scene.camera) scene.camera = framing_camera(b);
  if (!scene.has_emitter() && !scene.background)
    add_default_light(scene, usable(b) ? b : AABB{vec3(-1.0f), vec3(1.0f)});
}

}  // namespace pt
