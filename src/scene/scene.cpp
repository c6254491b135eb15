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

/// Half the length of b's diagonal, in double: its float square overflows for bounds beyond about 1e19 across.
float half_diagonal(const AABB& b) { return float(0.5 * glm::length(dvec3(b.extent()))); }

/// Adds a square rectangle light that lights what the camera sees, as a photographer's key light: above and behind
/// the camera (and a little to its right), facing the center of the bounds, outside their bounding sphere, its side
/// as long as the bounds' diameter, and bright enough for an irradiance of 2 at that center (a diffuse 0.8 surface
/// facing it then shows radiance ~0.5). A light straight above the bounds left the side the camera sees unlit
/// (issue 13: a statue's median pixel was 0.017).
void add_default_light(Scene& scene, const AABB& b, const Camera& cam) {
  const vec3 c = b.center();
  float radius = half_diagonal(b);
  if (!(radius > 0.0f) || !std::isfinite(radius)) radius = 1.0f;
  // The camera's frame (render/camera.h); a degenerate camera gets the default framing's frame. Lengths in double:
  // float squares overflow for scenes beyond about 1e19 (RenderGeometry::scale renders those).
  vec3 forward = vec3(glm::normalize(dvec3(cam.target) - dvec3(cam.eye)));
  vec3 right = glm::normalize(glm::cross(forward, cam.up));
  if (!is_finite(forward) || !is_finite(right)) forward = vec3(0, 0, -1), right = vec3(1, 0, 0);
  const vec3 up = glm::cross(right, forward);
  const vec3 dir = glm::normalize(-forward + 0.8f * up + 0.3f * right);  // from the center toward the light
  float eye_distance = float(glm::length(dvec3(cam.eye) - dvec3(c)));
  if (!std::isfinite(eye_distance)) eye_distance = 0.0f;
  // dir's -forward part is 0.76, so 1.5 times the eye's distance puts the light behind the eye.
  float distance = std::max(1.5f * eye_distance, 3.0f * radius);
  if (!std::isfinite(distance)) distance = 3.0f * radius;
  const float side = 2.0f * radius;
  // Edges a, b span the square with cross(a, b) = -dir: the front faces the bounds.
  const vec3 ua = glm::normalize(glm::cross(dir, up));
  const vec3 a = side * ua, e2 = side * glm::normalize(glm::cross(ua, dir));
  Material light;
  light.name = "default-light";
  light.albedo = vec3(0.0f);
  light.emission = vec3(float(2.0 / irradiance_per_radiance(side, side, distance)));
  Quad q;
  q.corner = c + distance * dir - 0.5f * (a + e2);
  q.edge1 = a;
  q.edge2 = e2;
  q.material = add_material(scene, light);
  scene.quads.push_back(q);
  scene.warnings.push_back(scene.source +
                           ": no light in the scene: added a default rectangle light above and behind the camera");
}

bool usable(const AABB& b) { return !b.empty() && is_finite(b.lo) && is_finite(b.hi); }

}  // namespace

AABB Scene::bounds() const {
  AABB b;
  for (const Mesh& m : meshes)
    for (uvec3 t : m.indices)
      for (int k = 0; k < 3; ++k) b.extend(m.world_position(t[k]));
  for (const Sphere& s : spheres) b.extend(s.bounds());
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
  float radius = half_diagonal(bounds);
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
    add_default_light(scene, usable(b) ? b : AABB{vec3(-1.0f), vec3(1.0f)}, *scene.camera);
}

}  // namespace pt
