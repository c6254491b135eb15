// Loading valid scenes: the MTL mapping, transforms, winding, warnings, built-in assets, default camera and light.
#include <gtest/gtest.h>

#include <filesystem>

#include "scene/builtin_assets.h"
#include "scene/json_locate.h"
#include "scene/load.h"
#include "scene/procedural.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

std::string good(const std::string& name) { return (fs::path(PTVIEW_TEST_DATA) / "good" / name).string(); }

const Material& material_of_face(const Scene& s, size_t face) { return s.materials[s.meshes[0].materials[face]]; }

bool has_warning(const Scene& s, const std::string& text) {
  for (const std::string& w : s.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(LoadObj, MtlMappingFollowsTheReadme) {
  Result<Scene> r = load_scene(good("materials.obj"));
  ASSERT_TRUE(r.ok()) << r.error();
  const Scene& s = *r;
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].indices.size(), 7u);
  const Material& red = material_of_face(s, 0);
  EXPECT_EQ(red.type, MaterialType::diffuse);
  EXPECT_FLOAT_EQ(red.albedo.x, 0.8f);
  EXPECT_FLOAT_EQ(red.albedo.y, 0.1f);
  const Material& light = material_of_face(s, 1);
  EXPECT_TRUE(light.emissive());
  EXPECT_FLOAT_EQ(light.emission.x, 5.0f);
  EXPECT_FLOAT_EQ(light.emission.z, 3.0f);
  const Material& mirror1 = material_of_face(s, 2);
  EXPECT_EQ(mirror1.type, MaterialType::specular);
  EXPECT_FLOAT_EQ(mirror1.albedo.y, 0.8f);  // albedo = Ks
  EXPECT_EQ(material_of_face(s, 3).type, MaterialType::specular);  // Ks dominant, Ns >= 500
  const Material& glass1 = material_of_face(s, 4);
  EXPECT_EQ(glass1.type, MaterialType::glass);
  EXPECT_FLOAT_EQ(glass1.ior, 1.33f);
  const Material& glass2 = material_of_face(s, 5);
  EXPECT_EQ(glass2.type, MaterialType::glass);
  EXPECT_FLOAT_EQ(glass2.ior, 1.7f);
  const Material& glass3 = material_of_face(s, 6);  // Tr > 0, no Ni
  EXPECT_EQ(glass3.type, MaterialType::glass);
  EXPECT_FLOAT_EQ(glass3.ior, 1.5f);
  // It has an emitter, so no default light; no camera in an OBJ, so one was made.
  EXPECT_EQ(s.quads.size(), 0u);
  ASSERT_TRUE(s.camera.has_value());
}

TEST(LoadObj, PolygonsAreTriangulatedAndNormalsKept) {
  Result<Scene> r = load_scene(good("quad_normals.obj"));
  ASSERT_TRUE(r.ok()) << r.error();
  const Mesh& m = r->meshes[0];
  EXPECT_EQ(m.indices.size(), 2u);
  ASSERT_EQ(m.normal_indices.size(), 2u);
  EXPECT_EQ(m.normals.size(), 1u);
  // Counter-clockwise seen from +z: the front normal is +z.
  vec3 a = m.positions[m.indices[0].x], b = m.positions[m.indices[0].y], c = m.positions[m.indices[0].z];
  EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
}

TEST(LoadObj, MissingMtlIsAWarningAndDefaultDiffuse) {
  Result<Scene> r = load_scene(good("missing_mtl.obj"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(has_warning(*r, "nowhere.mtl"));
  const Material& m = material_of_face(*r, 0);
  EXPECT_EQ(m.type, MaterialType::diffuse);
  EXPECT_FLOAT_EQ(m.albedo.x, 0.8f);
  // No emitter and no background: a default light above, with a warning.
  EXPECT_TRUE(has_warning(*r, "default rectangle light"));
  ASSERT_EQ(r->quads.size(), 1u);
  const Quad& q = r->quads[0];
  EXPECT_LT(glm::cross(q.edge1, q.edge2).y, 0.0f);  // faces down
  EXPECT_GT(q.corner.y, 1.0f);                       // above the bounds
}

TEST(LoadObj, DegenerateTrianglesAreDroppedWithAWarning) {
  Result<Scene> r = load_scene(good("with_degenerate.obj"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->meshes[0].indices.size(), 1u);
  EXPECT_TRUE(has_warning(*r, "1 degenerate"));
}

TEST(LoadObj, NegativeIndicesAreRelative) {
  Result<Scene> r = load_scene(good("negative_indices.obj"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->meshes[0].indices[0], uvec3(0, 1, 2));
}

TEST(LoadJson, TransformsScaleRotateTranslateInThatOrder) {
  Result<Scene> r = load_scene(good("transformed.json"));
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->meshes.size(), 2u);
  const Mesh& m = r->meshes[0];
  // (1, 0, 0) scaled by 2 -> (2, 0, 0), rotated 90 degrees about z -> (0, 2, 0), translated -> (10, 2, 0).
  EXPECT_NEAR(m.positions[1].x, 10.0f, 1e-5f);
  EXPECT_NEAR(m.positions[1].y, 2.0f, 1e-5f);
  EXPECT_NEAR(m.positions[1].z, 0.0f, 1e-5f);
  // The override material applies to every face.
  for (uint32_t id : m.materials) EXPECT_EQ(r->materials[id].name, "m");
  // Mirrored copy: winding swapped so the front still faces +z.
  const Mesh& mirrored = r->meshes[1];
  vec3 a = mirrored.positions[mirrored.indices[0].x], b = mirrored.positions[mirrored.indices[0].y],
       c = mirrored.positions[mirrored.indices[0].z];
  EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
  EXPECT_LT(mirrored.positions[1].x, 0.0f);
}

TEST(LoadJson, UnknownKeysWarnWithTheirLineAndBackgroundMeansNoDefaultLight) {
  Result<Scene> r = load_scene(good("typo_key.json"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(has_warning(*r, "typo_key.json:4: unknown key 'shapes[0].materail'"));
  EXPECT_TRUE(r->quads.empty());  // a background is given: exactly the light it describes
  EXPECT_FALSE(has_warning(*r, "default rectangle light"));
}

TEST(JsonLocate, FindsNestedValues) {
  std::string text = "{\n \"a\": [\n  1,\n  {\"b\": \"x\\\"y\",\n   \"c\": 3}\n ],\n \"d\": {}\n}";
  EXPECT_EQ(json_line_of(text, {}), 1);
  EXPECT_EQ(json_line_of(text, {"a"}), 2);
  EXPECT_EQ(json_line_of(text, {"a", "0"}), 3);
  EXPECT_EQ(json_line_of(text, {"a", "1", "b"}), 4);
  EXPECT_EQ(json_line_of(text, {"a", "1", "c"}), 5);
  EXPECT_EQ(json_line_of(text, {"d"}), 7);
  EXPECT_EQ(json_line_of(text, {"a", "7"}), 2);  // missing: the deepest existing ancestor
}

TEST(Builtin, EveryAssetLoadsWithCameraAndEmitter) {
  int n = 0;
  for (const BuiltinAsset& a : builtin_assets()) {
    Result<Scene> r = load_builtin_scene(a.name);
    ASSERT_TRUE(r.ok()) << a.name << ": " << r.error();
    EXPECT_TRUE(r->camera.has_value());
    EXPECT_TRUE(r->has_emitter()) << a.name;
    EXPECT_TRUE(r->warnings.empty()) << a.name << ": " << r->warnings[0];
    if (std::string(a.name) == "cornell-large-mesh") {
      EXPECT_GE(r->triangle_count(), 100000u);
    }
    ++n;
  }
  EXPECT_GE(n, 5);
  EXPECT_TRUE(load_builtin_scene(kDefaultSceneName).ok());
  EXPECT_FALSE(load_builtin_scene("nope").ok());
}

TEST(Procedural, TorusKnotIsClosedOutwardAndCounted) {
  TorusKnotParams p;
  p.segments = 64;
  p.sides = 12;
  Mesh m = make_torus_knot(p);
  EXPECT_EQ(m.indices.size(), size_t(2 * 64 * 12));
  // Closed and consistently oriented: every directed edge appears once and its reverse once.
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (uvec3 t : m.indices)
    for (int k = 0; k < 3; ++k) edges[{t[k], t[(k + 1) % 3]}]++;
  for (auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  EXPECT_GT(signed_volume(m), 0.0);
}

TEST(Finalize, DefaultCameraFramesTheBounds) {
  Scene s;
  s.source = "test";
  s.background = vec3(1.0f);
  s.spheres.push_back({vec3(10, 20, 30), 2.0f, 0});
  s.materials.push_back(Material{});
  finalize_scene(s);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->target, vec3(10, 20, 30));
  // The bounding sphere (radius 2 sqrt 3) fits in the vertical field of view.
  float d = glm::length(s.camera->eye - s.camera->target);
  EXPECT_GT(std::sin(glm::radians(s.camera->fov_deg / 2)) * d, 2.0f * std::sqrt(3.0f));
  EXPECT_TRUE(s.quads.empty());
}

TEST(LoadObj, BunnyLoadsWhenPresent) {
  fs::path bunny = fs::path(PTVIEW_SOURCE_DIR) / ".." / "shared" / "models" / "stanford-bunny.obj";
  if (!fs::exists(bunny)) GTEST_SKIP() << "no " << bunny;
  Result<Scene> r = load_scene(bunny.string());
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->meshes[0].indices.size(), 69451u);
}

}  // namespace
}  // namespace pt
