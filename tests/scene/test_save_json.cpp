// The scene writer (the viewer's "save scene") against the loader: a scene with every part the JSON schema has
// (camera, background, every material type with non-default values, quads, spheres, a mesh named by its OBJ file
// with a transform, a mesh with its own materials per triangle far from the origin that has no file) loads back as
// the same scene.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "scene/load.h"
#include "scene/save_json.h"
#include "temp_dir.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

using test::TempDir;

void expect_near(vec3 a, vec3 b, float tolerance, const std::string& what) {
  EXPECT_LE(glm::length(a - b), tolerance) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") against ("
                                           << b.x << ", " << b.y << ", " << b.z << ")";
}

void expect_same_material(const Material& a, const Material& b, const std::string& what) {
  EXPECT_EQ(a.type, b.type) << what;
  expect_near(a.albedo, b.albedo, 1e-6f, what + " albedo");
  expect_near(a.emission, b.emission, 1e-6f, what + " emission");
  if (info_of(a.type).uses_ior) {
    EXPECT_FLOAT_EQ(a.ior, b.ior) << what;
  }
}

/// The loaded scene with what the writer has to keep that the file cannot express: an edited glass, an emitter, a
/// mesh made in code.
Scene make_scene(const TempDir& dir) {
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 2 0\nv 1 2 -1\nf 1 2 3\nf 2 4 3\n");
  const std::string json = dir.write("in.json", R"({
    "camera": {"eye": [1, 2, 3], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 37.5},
    "background": [0.1, 0.2, 0.3],
    "materials": {"paint": {"type": "diffuse", "albedo": [0.2, 0.4, 0.6]}},
    "shapes": [{"type": "mesh", "file": "tri.obj", "material": "paint",
                "transform": {"scale": [2, 1, 0.5], "rotate": [0, 1, 1, 30], "translate": [5, -1, 2]}}]})");
  Result<Scene> loaded = load_scene(json);
  EXPECT_TRUE(loaded.ok()) << loaded.error();
  Scene s = std::move(loaded.value());
  Material mirror{"mirror", MaterialType::specular, vec3(0.9f, 0.8f, 0.7f)};
  Material water{"water", MaterialType::glass, vec3(1.0f), 1.33f};
  Material lamp{"lamp", MaterialType::diffuse, vec3(0.5f), 1.5f, vec3(3.0f, 2.0f, 1.0f)};
  s.materials.push_back(mirror);
  s.materials.push_back(water);
  s.materials.push_back(lamp);
  const uint32_t paint = 0, m_mirror = uint32_t(s.materials.size() - 3), m_water = m_mirror + 1, m_lamp = m_mirror + 2;
  s.quads.push_back({vec3(-1, 3, -1), vec3(2, 0, 0), vec3(0, 0, 1.5f), m_lamp});
  s.spheres.push_back({{vec3(0.5f, 1, 0), 0.25f}, m_water});
  s.spheres.push_back({{vec3(-0.5f, 1, 0), 0.5f}, m_mirror});
  // Two materials without a name (made in code): each is saved under a name of its own.
  s.materials.push_back(Material{"", MaterialType::diffuse, vec3(0.1f, 0.7f, 0.2f)});
  s.spheres.push_back({{vec3(1.5f, 1, 0), 0.2f}, uint32_t(s.materials.size() - 1)});
  s.materials.push_back(Material{"", MaterialType::diffuse, vec3(0.6f, 0.3f, 0.9f)});
  s.spheres.push_back({{vec3(2.5f, 1, 0), 0.2f}, uint32_t(s.materials.size() - 1)});
  Mesh far;  // made in code, 1e5 from the origin, a material per triangle
  far.name = "far";
  far.origin = dvec3(1e5, 0.0, -2.0);
  far.positions = {vec3(0, 0, 0), vec3(0.001f, 0, 0), vec3(0, 0.001f, 0), vec3(0.001f, 0.001f, 0.0005f),
                   vec3(0.002f, 0.001f, 0)};
  for (vec3& p : far.positions)  // an ulp off the short decimals: nine digits are needed to read them back
    for (int a = 0; a < 3; ++a)
      if (p[a] != 0.0f) p[a] = std::nextafter(p[a], 1.0f);
  far.indices = {uvec3(0, 1, 2), uvec3(1, 3, 2), uvec3(1, 4, 3), uvec3(0, 4, 1)};
  far.materials = {m_water, paint, m_lamp, m_mirror};  // every type, and an emitter, through the written MTL
  far.normals = {glm::normalize(vec3(0.1f, 0.2f, 1.0f)), vec3(0, 0, 1), glm::normalize(vec3(-0.3f, 0.0f, 1.0f))};
  far.normal_indices = {uvec3(0, 1, 2), uvec3(1, 2, 0), uvec3(2, 2, 1), uvec3(0, 0, 0)};
  s.meshes.push_back(far);
  return s;
}

TEST(SaveJson, EveryPartOfASceneLoadsBackTheSame) {
  TempDir dir;
  const Scene s = make_scene(dir);
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_FALSE(s.meshes[0].source.file.empty());  // the first mesh is named by its file, with its transform
  fs::create_directory(dir.path / "saved");  // a folder of its own: the mesh file is named relative to it
  const std::string out = (dir.path / "saved" / "scene.json").string();
  const std::optional<Error> err = save_scene_json(s, s.materials, out);
  ASSERT_FALSE(err.has_value()) << err->message;
  Result<Scene> back_or = load_scene(out);
  ASSERT_TRUE(back_or.ok()) << back_or.error();
  const Scene& back = back_or.value();

  ASSERT_TRUE(back.camera.has_value());
  expect_near(back.camera->eye, s.camera->eye, 1e-6f, "eye");
  expect_near(back.camera->target, s.camera->target, 1e-6f, "target");
  expect_near(back.camera->up, s.camera->up, 1e-6f, "up");
  EXPECT_FLOAT_EQ(back.camera->fov_deg, s.camera->fov_deg);
  ASSERT_TRUE(back.background.has_value());
  expect_near(*back.background, *s.background, 1e-6f, "background");

  ASSERT_EQ(back.quads.size(), s.quads.size());
  for (size_t i = 0; i < s.quads.size(); ++i) {
    expect_near(back.quads[i].corner, s.quads[i].corner, 1e-6f, "quad corner");
    expect_near(back.quads[i].edge1, s.quads[i].edge1, 1e-6f, "quad edge1");
    expect_near(back.quads[i].edge2, s.quads[i].edge2, 1e-6f, "quad edge2");
    expect_same_material(back.materials[back.quads[i].material], s.materials[s.quads[i].material], "quad");
  }
  ASSERT_EQ(back.spheres.size(), s.spheres.size());
  for (size_t i = 0; i < s.spheres.size(); ++i) {
    expect_near(back.spheres[i].center, s.spheres[i].center, 1e-6f, "sphere center");
    EXPECT_FLOAT_EQ(back.spheres[i].radius, s.spheres[i].radius);
    expect_same_material(back.materials[back.spheres[i].material], s.materials[s.spheres[i].material], "sphere");
  }
  ASSERT_EQ(back.meshes.size(), s.meshes.size());
  for (size_t m = 0; m < s.meshes.size(); ++m) {
    const Mesh &a = s.meshes[m], &b = back.meshes[m];
    ASSERT_EQ(b.indices.size(), a.indices.size()) << "mesh " << m;
    for (size_t t = 0; t < a.indices.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        // In double, relative to the scene: the far mesh's 1e-3 triangles must keep their shape.
        const dvec3 pa = a.origin + dvec3(a.positions[a.indices[t][k]]);
        const dvec3 pb = b.origin + dvec3(b.positions[b.indices[t][k]]);
        EXPECT_LE(glm::length(pa - pb), 1e-6 * (1.0 + glm::length(pa))) << "mesh " << m << " triangle " << t;
        if (m == 1) {  // the written mesh: its numbers are written so that they read back as the same floats
          EXPECT_EQ(pa, pb) << "triangle " << t << " corner " << k;
          ASSERT_EQ(b.normal_indices.size(), b.indices.size()) << "the shading normals were kept";
          expect_near(b.normals[b.normal_indices[t][k]], a.normals[a.normal_indices[t][k]], 1e-6f, "normal");
        }
      }
      const uint32_t ma = a.materials.empty() ? 0 : a.materials[t], mb = b.materials.empty() ? 0 : b.materials[t];
      expect_same_material(back.materials[mb], s.materials[ma], "mesh " + std::to_string(m));
    }
  }
  // The file-named mesh is still named by its file (relative to the saved JSON), not copied.
  EXPECT_EQ(fs::path(back.meshes[0].source.file).filename(), "tri.obj");
  EXPECT_FALSE(fs::exists(dir.path / "saved" / "scene.mesh0.obj"));
  EXPECT_TRUE(fs::exists(dir.path / "saved" / "scene.mesh1.obj"));
  // Named relative to the saved scene: the saved folder and the mesh file, moved together, still load.
  fs::create_directory(dir.path / "moved");
  fs::rename(dir.path / "saved", dir.path / "moved" / "saved");
  fs::rename(dir.path / "tri.obj", dir.path / "moved" / "tri.obj");
  Result<Scene> moved = load_scene((dir.path / "moved" / "saved" / "scene.json").string());
  EXPECT_TRUE(moved.ok()) << moved.error();
}

// A mesh whose faces use its OBJ's own materials is named by its file while those materials are as loaded; once one
// is edited, the saved scene writes the mesh (and its MTL) out, so the edit is kept.
TEST(SaveJson, AMeshWithEditedFileMaterialsIsWrittenOut) {
  TempDir dir;
  dir.write("lit.mtl", "newmtl wall\nKd 0.5 0.5 0.5\n");
  dir.write("lit.obj", "mtllib lit.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl wall\nf 1 2 3\n");
  Result<Scene> loaded = load_scene(dir.write("in.json", R"({"shapes": [{"type": "mesh", "file": "lit.obj"}]})"));
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  Scene s = std::move(loaded.value());
  ASSERT_TRUE(s.meshes.at(0).source.file_materials);
  const std::vector<Material> as_loaded = s.materials;
  for (bool edited : {false, true}) {
    if (edited) s.materials[s.meshes[0].materials[0]].albedo = vec3(0.9f, 0.1f, 0.1f);
    const std::string out = dir / (edited ? "edited.json" : "same.json");
    const std::optional<Error> err = save_scene_json(s, as_loaded, out);
    ASSERT_FALSE(err.has_value()) << err->message;
    Result<Scene> back = load_scene(out);
    ASSERT_TRUE(back.ok()) << back.error();
    expect_same_material(back->materials[back->meshes.at(0).materials.at(0)], s.materials[s.meshes[0].materials[0]],
                         edited ? "edited" : "as loaded");
    EXPECT_EQ(fs::exists(dir.path / (edited ? "edited.mesh0.obj" : "same.mesh0.obj")), edited);
  }
}

}  // namespace
}  // namespace pt
