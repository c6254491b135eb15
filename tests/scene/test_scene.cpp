// Scene-level facts: bounds, which materials count as emitters, and finalize_scene's default camera (frames the
// bounds) and default light (only without emitter and background; irradiance about 2 at the top of the bounds).
#include <gtest/gtest.h>

#include "scene/scene.h"

namespace pt {
namespace {

Scene scene_with_sphere(vec3 center, float radius) {
  Scene s;
  s.source = "test-scene";
  s.materials.push_back(Material{"grey"});
  s.spheres.push_back({center, radius, 0});
  return s;
}

/// Irradiance on an upward-facing point `x` from the emissive quads of `s`, by midpoint quadrature over each quad
/// (E = integral of L cos(theta) cos(theta') / r^2 dA), independent of how finalize_scene chose the radiance.
double irradiance_from_quads(const Scene& s, vec3 x) {
  double e = 0.0;
  const int n = 400;
  for (const Quad& q : s.quads) {
    const Material& m = s.materials[q.material];
    if (!m.emissive()) continue;
    dvec3 normal = glm::normalize(glm::cross(dvec3(q.edge1), dvec3(q.edge2)));
    double area = glm::length(glm::cross(dvec3(q.edge1), dvec3(q.edge2)));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        dvec3 y = dvec3(q.corner) + (i + 0.5) / n * dvec3(q.edge1) + (j + 0.5) / n * dvec3(q.edge2);
        dvec3 d = y - dvec3(x);
        double r2 = glm::dot(d, d);
        dvec3 w = d / std::sqrt(r2);
        double cos_receiver = std::max(0.0, w.y), cos_emitter = std::max(0.0, -glm::dot(w, normal));
        e += m.emission.x * cos_receiver * cos_emitter / r2 * area / (n * n);
      }
  }
  return e;
}

TEST(Scene, BoundsCoverEveryShape) {
  Scene s = scene_with_sphere(vec3(0, 0, 0), 1.0f);
  s.quads.push_back({vec3(5, 0, 0), vec3(0, 2, 0), vec3(0, 0, 3), 0});
  Mesh m;
  m.positions = {vec3(-4, 0, 0), vec3(-4, 1, 0), vec3(-4, 0, 1), vec3(100, 100, 100)};  // the last is unused
  m.indices = {uvec3(0, 1, 2)};
  m.materials = {0};
  s.meshes.push_back(m);
  AABB b = s.bounds();
  EXPECT_EQ(b.lo, vec3(-4, -1, -1));
  EXPECT_EQ(b.hi, vec3(5, 2, 3));
  EXPECT_TRUE(Scene{}.bounds().empty());
}

TEST(Scene, OnlyUsedEmissiveMaterialsAreEmitters) {
  Scene s = scene_with_sphere(vec3(0), 1.0f);
  Material light{"light"};
  light.emission = vec3(0, 0, 1);
  s.materials.push_back(light);  // defined, not used
  EXPECT_FALSE(s.has_emitter());
  s.quads.push_back({vec3(0), vec3(1, 0, 0), vec3(0, 1, 0), 1});
  EXPECT_TRUE(s.has_emitter());
  s.quads.clear();
  Mesh m;
  m.positions = {vec3(0), vec3(1, 0, 0), vec3(0, 1, 0)};
  m.indices = {uvec3(0, 1, 2)};
  m.materials = {1};
  s.meshes.push_back(m);
  EXPECT_TRUE(s.has_emitter());
}

TEST(Finalize, DefaultCameraFramesTheBoundsWithAMargin) {
  Scene s = scene_with_sphere(vec3(10, 20, 30), 2.0f);
  s.background = vec3(1.0f);
  finalize_scene(s);
  ASSERT_TRUE(s.camera.has_value());
  const Camera& c = *s.camera;
  EXPECT_EQ(c.target, vec3(10, 20, 30));
  EXPECT_FLOAT_EQ(c.fov_deg, 40.0f);
  EXPECT_EQ(c.up, vec3(0, 1, 0));
  EXPECT_NEAR(c.eye.x, 10.0f, 1e-5f);
  EXPECT_NEAR(c.eye.y, 20.0f, 1e-5f);
  EXPECT_GT(c.eye.z, 30.0f);
  // The bounding sphere of the bounds (radius 2 sqrt 3) subtends 20 degrees / 1.1 from the eye: inside the field
  // of view, with its 10% margin, and not far more distant than needed.
  float r = 2.0f * std::sqrt(3.0f), d = glm::length(c.eye - c.target);
  float half_angle = glm::degrees(std::asin(r / d));
  EXPECT_LT(half_angle, 20.0f / 1.05f);
  EXPECT_GT(half_angle, 20.0f / 1.2f);
  // A background means the scene's light is exactly what it describes: none added.
  EXPECT_TRUE(s.quads.empty());
  EXPECT_TRUE(s.warnings.empty());
}

TEST(Finalize, KeepsAGivenCamera) {
  Scene s = scene_with_sphere(vec3(0), 1.0f);
  s.background = vec3(0.0f);  // black, but given: still no default light
  Camera mine;
  mine.eye = vec3(1, 2, 3);
  s.camera = mine;
  finalize_scene(s);
  EXPECT_EQ(s.camera->eye, vec3(1, 2, 3));
  EXPECT_TRUE(s.quads.empty());
}

TEST(Finalize, DefaultLightAboveFacingDownWithIrradianceAboutTwo) {
  for (vec3 half : {vec3(1.0f), vec3(3.0f, 0.5f, 0.2f), vec3(0.01f, 2.0f, 0.01f), vec3(5.0f, 0.0f, 5.0f)}) {
    SCOPED_TRACE(::testing::Message() << half.x << " " << half.y << " " << half.z);
    Scene s;
    s.source = "box.obj";
    s.materials.push_back(Material{"grey"});
    s.quads.push_back({vec3(-half.x, -half.y, -half.z), vec3(2 * half.x, 0, 0), vec3(0, 2 * half.y, 2 * half.z), 0});
    AABB before = s.bounds();
    finalize_scene(s);
    ASSERT_EQ(s.quads.size(), 2u);
    const Quad& q = s.quads[1];
    const Material& m = s.materials[q.material];
    EXPECT_TRUE(m.emissive());
    EXPECT_EQ(m.albedo, vec3(0.0f));  // the light's back does not reflect
    vec3 n = glm::cross(q.edge1, q.edge2);
    EXPECT_GT(glm::length(n), 0.0f);  // positive size even for flat bounds
    EXPECT_LT(n.y, 0.0f);             // faces down
    EXPECT_EQ(n.x, 0.0f);
    EXPECT_EQ(n.z, 0.0f);
    vec3 center = q.corner + 0.5f * (q.edge1 + q.edge2);
    EXPECT_NEAR(center.x, before.center().x, 1e-5f);
    EXPECT_NEAR(center.z, before.center().z, 1e-5f);
    float largest = max_component(before.extent());
    EXPECT_NEAR(center.y, before.hi.y + 0.5f * largest, 1e-5f);
    double e = irradiance_from_quads(s, vec3(before.center().x, before.hi.y, before.center().z));
    EXPECT_NEAR(e, 2.0, 0.02);
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_EQ(s.warnings[0], "box.obj: no light in the scene: added a default rectangle light above it");
    // Finalizing again adds nothing: the scene has a light now.
    finalize_scene(s);
    EXPECT_EQ(s.quads.size(), 2u);
  }
}

TEST(Finalize, AnEmptySceneGetsASaneCameraAndLight) {
  Scene s;
  s.source = "empty.json";
  finalize_scene(s);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_TRUE(is_finite(s.camera->eye));
  EXPECT_GT(glm::length(s.camera->eye - s.camera->target), 0.0f);
  ASSERT_EQ(s.quads.size(), 1u);
  EXPECT_TRUE(is_finite(s.quads[0].corner));
  EXPECT_TRUE(s.has_emitter());
}

TEST(Finalize, APointSizedSceneStillGetsAUsableCamera) {
  Scene s = scene_with_sphere(vec3(3, 4, 5), 1e-30f);
  s.background = vec3(1.0f);
  finalize_scene(s);
  EXPECT_TRUE(is_finite(s.camera->eye));
  EXPECT_GT(glm::length(s.camera->eye - s.camera->target), 0.0f);
}

TEST(Finalize, AnExistingEmitterMeansNoDefaultLight) {
  Scene s = scene_with_sphere(vec3(0), 1.0f);
  s.materials[0].emission = vec3(1.0f);
  finalize_scene(s);
  EXPECT_TRUE(s.quads.empty());
  EXPECT_TRUE(s.warnings.empty());
}

}  // namespace
}  // namespace pt
