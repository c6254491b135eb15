// Scene-level facts: bounds, which materials count as emitters, and finalize_scene's default camera (frames the
// bounds) and default light (only without emitter and background; a key light above and behind the camera with an
// irradiance of about 2 at the center of the bounds).
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

/// Irradiance on a point `x` facing `up` from the emissive quads of `s`, by midpoint quadrature over each quad
/// (E = integral of L cos(theta) cos(theta') / r^2 dA), independent of how finalize_scene chose the radiance.
double irradiance_from_quads(const Scene& s, vec3 x, dvec3 up = dvec3(0, 1, 0)) {
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
        double cos_receiver = std::max(0.0, glm::dot(w, up)), cos_emitter = std::max(0.0, -glm::dot(w, normal));
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
  // A quad turned in its plane: its fourth corner (corner + both edges) reaches farther than the other three.
  Scene turned;
  turned.quads.push_back({vec3(0, 0, 0), vec3(1, 1, 0), vec3(1, -1, 0.5f), 0});
  EXPECT_EQ(turned.bounds().lo, vec3(0, -1, 0));
  EXPECT_EQ(turned.bounds().hi, vec3(2, 1, 0.5f));
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

TEST(Finalize, DefaultLightIsAKeyLightAboveAndBehindTheCamera) {
  // Issue 13: the light must light the side the camera sees. Default framing cameras and given ones, flat bounds.
  const Camera side_view{vec3(40, 3, -2), vec3(0.5f, 0, 0), vec3(0, 1, 0), 30.0f};
  for (vec3 half : {vec3(1.0f), vec3(3.0f, 0.5f, 0.2f), vec3(0.01f, 2.0f, 0.01f), vec3(5.0f, 0.0f, 5.0f)})
    for (bool given_camera : {false, true}) {
      SCOPED_TRACE(::testing::Message() << half.x << " " << half.y << " " << half.z << " camera " << given_camera);
      Scene s;
      s.source = "box.obj";
      s.materials.push_back(Material{"grey"});
      s.quads.push_back({vec3(-half.x, -half.y, -half.z), vec3(2 * half.x, 0, 0), vec3(0, 2 * half.y, 2 * half.z), 0});
      if (given_camera) s.camera = side_view;
      AABB before = s.bounds();
      finalize_scene(s);
      ASSERT_EQ(s.quads.size(), 2u);
      const Quad& q = s.quads[1];
      const Material& m = s.materials[q.material];
      EXPECT_TRUE(m.emissive());
      EXPECT_EQ(m.albedo, vec3(0.0f));  // the light's back does not reflect
      const Camera& cam = *s.camera;
      vec3 forward = glm::normalize(cam.target - cam.eye);
      vec3 up = glm::cross(glm::normalize(glm::cross(forward, cam.up)), forward);
      vec3 center = q.corner + 0.5f * (q.edge1 + q.edge2), c = before.center();
      vec3 n = glm::cross(q.edge1, q.edge2);
      float radius = 0.5f * glm::length(before.extent());
      EXPECT_GT(glm::dot(n, c - center), 0.0f);                   // faces the bounds
      EXPECT_GT(glm::dot(center - cam.eye, up), 0.0f);            // above the camera
      EXPECT_LT(glm::dot(center - cam.eye, forward), 0.0f);       // behind it
      EXPECT_GT(glm::length(center - c), 2.0f * radius);          // clear of the bounds
      EXPECT_NEAR(glm::length(q.edge1), 2.0f * radius, 1e-4f);  // sized to the bounds
      EXPECT_NEAR(glm::length(q.edge2), 2.0f * radius, 1e-4f);
      double e = irradiance_from_quads(s, c, glm::normalize(dvec3(center - c)));
      EXPECT_NEAR(e, 2.0, 0.02);
      ASSERT_EQ(s.warnings.size(), 1u);
      EXPECT_EQ(s.warnings[0], "box.obj: no light in the scene: added a default rectangle light above and behind the camera");
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

// A small scene far from the origin along the view axis: an eye at a few of its radii would round onto the target
// (the float spacing there is larger than the distance), so the framing keeps the eye a hundred float steps or more
// away (a hundred thousandth of its distance from the origin), and the camera still looks at the scene.
TEST(Finalize, ASmallSceneFarAlongTheViewAxisStillGetsAViewDirection) {
  Scene s = scene_with_sphere(vec3(0.5f, -0.25f, 3.0e7f), 1e-3f);
  s.background = vec3(1.0f);
  finalize_scene(s);
  const dvec3 view = dvec3(s.camera->target) - dvec3(s.camera->eye);
  ASSERT_GT(glm::length(view), 0.0);
  EXPECT_GT(glm::length(view), 100 * 2.0) << "at least a hundred float steps (2 apart at 3e7)";
  EXPECT_GT(glm::dot(glm::normalize(view), dvec3(0, 0, -1)), 0.999);
}

// An out-of-range camera index names the file and how many cameras it defines, in the singular for one.
TEST(Scene, AnOutOfRangeCameraNamesHowManyTheFileDefines) {
  Scene s;
  s.source = "a.gltf";
  EXPECT_EQ(select_camera(s, 0), "camera 0 out of range (a.gltf defines 0 perspective cameras)");
  s.cameras.push_back(Camera{});
  EXPECT_EQ(select_camera(s, 1), "camera 1 out of range (a.gltf defines 1 perspective camera)");
  s.cameras.push_back(Camera{});
  EXPECT_EQ(select_camera(s, 5), "camera 5 out of range (a.gltf defines 2 perspective cameras)");
  EXPECT_EQ(select_camera(s, 1), "");
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
