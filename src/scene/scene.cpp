#include <cmath>

#include "scene/scene.h"

namespace pt {

AABB Scene::bounds() const {
  AABB b;
  for (const Mesh& m : meshes)
    for (vec3 p : m.positions) b.extend(p);
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

void finalize_scene(Scene& scene) {
  AABB b = scene.bounds();
  bool usable = !b.empty() && is_finite(b.lo) && is_finite(b.hi);
  vec3 center = usable ? b.center() : vec3(0.0f);
  vec3 extent = usable ? b.extent() : vec3(2.0f);
  float max_extent = std::max(max_component(extent), 1e-3f);
  if (!scene.camera) {
    // Fit the bounding sphere in a 40-degree vertical field of view with a 10% margin, looking down -z.
    Camera cam;
    cam.fov_deg = 40.0f;
    float radius = std::max(0.5f * glm::length(extent), 1e-3f);
    float dist = 1.1f * radius / std::sin(glm::radians(0.5f * cam.fov_deg));
    cam.target = center;
    cam.eye = center + vec3(0.0f, 0.0f, dist);
    cam.up = vec3(0.0f, 1.0f, 0.0f);
    scene.camera = cam;
  }
  if (!scene.has_emitter() && !scene.background) {
    // A rectangle light above the bounds, facing down, bright enough for an irradiance of about 2 at the top.
    float h = 0.5f * max_extent;
    float sx = std::max(0.5f * extent.x, 0.25f * max_extent);
    float sz = std::max(0.5f * extent.z, 0.25f * max_extent);
    float area = sx * sz;
    float radiance = 2.0f * h * h / area + 1.0f;
    Material light;
    light.name = "default-light";
    light.albedo = vec3(0.0f);
    light.emission = vec3(radiance);
    scene.materials.push_back(light);
    Quad q;
    float top = usable ? b.hi.y : 1.0f;
    q.corner = vec3(center.x - 0.5f * sx, top + h, center.z - 0.5f * sz);
    q.edge1 = vec3(sx, 0.0f, 0.0f);
    q.edge2 = vec3(0.0f, 0.0f, sz);  // cross(edge1, edge2) = -y: faces down
    q.material = uint32_t(scene.materials.size() - 1);
    scene.quads.push_back(q);
    scene.warnings.push_back(scene.source + ": no light in the scene: added a default rectangle light above it");
  }
}

}  // namespace pt
