// Loading entry points and the built-in scenes: every asset parses with its camera and light, its walls face the
// inside, its objects stand on the floor inside the box without touching walls or each other, its blocks are
// closed outward, and the large-mesh scene is large.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include "fifo_watchdog.h"
#include "scene/builtin_assets.h"
#include "scene/load.h"
#include "scene/load_internal.h"
#include "temp_dir.h"

namespace pt {
namespace {

bool inside_box(vec3 p, float tolerance = 1e-4f) {
  return p.x >= -1 - tolerance && p.x <= 1 + tolerance && p.y >= -tolerance && p.y <= 2 + tolerance &&
         p.z >= -1 - tolerance && p.z <= 1 + tolerance;
}

/// Distance from p to a rectangle (a quad whose edges are perpendicular).
float distance_to_rectangle(vec3 p, const Quad& q) {
  vec3 d = p - q.corner;
  float a = std::clamp(glm::dot(d, q.edge1) / glm::dot(q.edge1, q.edge1), 0.0f, 1.0f);
  float b = std::clamp(glm::dot(d, q.edge2) / glm::dot(q.edge2, q.edge2), 0.0f, 1.0f);
  return glm::length(p - (q.corner + a * q.edge1 + b * q.edge2));
}

/// The walls are the quads spanning a whole side of the box [-1,1] x [0,2] x [-1,1].
bool is_wall(const Quad& q) { return glm::length(glm::cross(q.edge1, q.edge2)) > 3.99f; }

TEST(Builtin, EveryAssetIsACornellBoxWithCameraAndLight) {
  size_t n = 0;
  for (const BuiltinAsset& a : builtin_assets()) {
    SCOPED_TRACE(a.name);
    ++n;
    Result<Scene> r = load_builtin_scene(a.name);
    ASSERT_TRUE(r.ok()) << r.error();
    const Scene& s = *r;
    EXPECT_EQ(s.source, std::string("builtin:") + a.name);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    EXPECT_FALSE(s.background.has_value());
    ASSERT_TRUE(s.camera.has_value());
    EXPECT_EQ(s.camera->eye, vec3(0.0f, 1.0f, 3.9f));
    EXPECT_EQ(s.camera->target, vec3(0.0f, 1.0f, 0.0f));
    EXPECT_FLOAT_EQ(s.camera->fov_deg, 40.0f);
    EXPECT_TRUE(s.has_emitter());

    size_t walls = 0, lights = 0;
    for (const Quad& q : s.quads) {
      vec3 n_front = glm::cross(q.edge1, q.edge2), center = q.corner + 0.5f * (q.edge1 + q.edge2);
      EXPECT_NEAR(glm::dot(q.edge1, q.edge2), 0.0f, 1e-4f);  // rectangles
      for (vec3 c : {q.corner, q.corner + q.edge1, q.corner + q.edge2, q.corner + q.edge1 + q.edge2})
        EXPECT_TRUE(inside_box(c)) << c.x << " " << c.y << " " << c.z;
      const Material& m = s.materials[q.material];
      if (is_wall(q)) {
        ++walls;
        EXPECT_GT(glm::dot(n_front, vec3(0, 1, 0) - center), 0.0f) << "a wall faces out of the box";
        EXPECT_FALSE(m.emissive());
      } else if (m.emissive()) {
        ++lights;
        EXPECT_EQ(m.emission, vec3(17, 12, 4));
        EXPECT_NEAR(center.y, 1.98f, 1e-5f);
        EXPECT_NEAR(center.x, 0.0f, 1e-5f);
        EXPECT_NEAR(center.z, 0.0f, 1e-5f);
        EXPECT_LT(n_front.y, 0.0f);  // shines down
        EXPECT_NEAR(glm::length(n_front), 0.47f * 0.38f, 1e-4f);
      }
    }
    EXPECT_EQ(walls, 5u);  // open at z = +1
    EXPECT_EQ(lights, 1u);
    // Spheres: inside the box, resting on the floor, clear of walls, blocks and each other.
    for (size_t i = 0; i < s.spheres.size(); ++i) {
      const Sphere& sp = s.spheres[i];
      EXPECT_NEAR(sp.center.y - sp.radius, 0.0f, 1e-5f);
      EXPECT_TRUE(inside_box(sp.center - vec3(sp.radius)) && inside_box(sp.center + vec3(sp.radius)));
      for (const Quad& q : s.quads)
        if (!(is_wall(q) && q.corner.y == 0.0f && q.edge1.y == 0.0f && q.edge2.y == 0.0f)) {  // all but the floor
          EXPECT_GT(distance_to_rectangle(sp.center, q), sp.radius + 0.05f);
        }
      for (size_t j = i + 1; j < s.spheres.size(); ++j)
        EXPECT_GT(glm::length(sp.center - s.spheres[j].center), sp.radius + s.spheres[j].radius + 0.05f);
    }
    // Meshes: inside, standing on the floor (a hair above it).
    for (const Mesh& m : s.meshes) {
      AABB b;
      for (uint32_t i = 0; i < m.positions.size(); ++i) b.extend(m.world_position(i));
      EXPECT_TRUE(inside_box(b.lo) && inside_box(b.hi));
      EXPECT_GT(b.lo.y, 0.0f);
      EXPECT_LT(b.lo.y, 0.005f);
      EXPECT_LT(b.hi.y, 1.9f);  // below the light
    }
  }
  EXPECT_GE(n, 5u);
}

/// Volume enclosed by the non-wall, non-light quads, by the divergence theorem: on each planar face p . n is
/// constant, so V = sum of (center . (edge1 x edge2)) / 3. A face on the floor (missing, as the blocks have no
/// bottom) would add 0, so open-bottomed blocks still measure their volume -- and any inward face changes it.
double block_volume(const Scene& s) {
  double v = 0.0;
  for (const Quad& q : s.quads) {
    if (is_wall(q) || s.materials[q.material].emissive()) continue;
    dvec3 center = dvec3(q.corner) + 0.5 * (dvec3(q.edge1) + dvec3(q.edge2));
    v += glm::dot(center, glm::cross(dvec3(q.edge1), dvec3(q.edge2))) / 3.0;
  }
  return v;
}

TEST(Builtin, ClassicBlocksAreClosedOutwardAndSized) {
  Result<Scene> r = load_builtin_scene("cornell");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->quads.size(), 5u + 1u + 2u * 5u);  // walls, light, two blocks of five faces
  EXPECT_NEAR(block_volume(*r), 0.6 * 0.6 * 1.2 + 0.6 * 0.6 * 0.6, 1e-3);
  // Both blocks stand on the floor, the tall one at the back left, the short one at the front right.
  AABB tall, short_block;
  for (const Quad& q : r->quads) {
    if (is_wall(q) || r->materials[q.material].emissive()) continue;
    vec3 c = q.corner + 0.5f * (q.edge1 + q.edge2);
    AABB& b = glm::length(vec2(c.x, c.z) - vec2(-0.33f, -0.265f)) < 0.45f ? tall : short_block;
    for (vec3 p : {q.corner, q.corner + q.edge1, q.corner + q.edge2, q.corner + q.edge1 + q.edge2}) b.extend(p);
  }
  EXPECT_NEAR(tall.hi.y, 1.2f, 1e-4f);
  EXPECT_NEAR(short_block.hi.y, 0.6f, 1e-4f);
  EXPECT_EQ(tall.lo.y, 0.0f);
  EXPECT_EQ(short_block.lo.y, 0.0f);
  EXPECT_LT(tall.center().x, 0.0f);
  EXPECT_LT(tall.center().z, 0.0f);
  EXPECT_GT(short_block.center().x, 0.0f);
  EXPECT_GT(short_block.center().z, 0.0f);
}

TEST(Builtin, EachSceneHasItsMaterials) {
  auto types = [](const Scene& s) {
    std::vector<MaterialType> t;
    for (const Sphere& sp : s.spheres) t.push_back(s.materials[sp.material].type);
    std::sort(t.begin(), t.end());
    return t;
  };
  Result<Scene> glass = load_builtin_scene("cornell-glass");
  ASSERT_TRUE(glass.ok());
  EXPECT_EQ(types(*glass), (std::vector{MaterialType::diffuse, MaterialType::glass}));
  for (const Sphere& sp : glass->spheres)
    if (glass->materials[sp.material].type == MaterialType::glass) {
      EXPECT_FLOAT_EQ(glass->materials[sp.material].ior, 1.5f);
    }
  Result<Scene> mirror = load_builtin_scene("cornell-mirror");
  ASSERT_TRUE(mirror.ok());
  EXPECT_EQ(types(*mirror), (std::vector{MaterialType::diffuse, MaterialType::specular}));
  Result<Scene> spheres = load_builtin_scene(kDefaultSceneName);
  ASSERT_TRUE(spheres.ok());
  EXPECT_EQ(spheres->source, "builtin:cornell-spheres");
  EXPECT_EQ(types(*spheres), (std::vector{MaterialType::specular, MaterialType::glass}));
  Result<Scene> large = load_builtin_scene("cornell-large-mesh");
  ASSERT_TRUE(large.ok());
  ASSERT_EQ(large->meshes.size(), 1u);
  EXPECT_GE(large->meshes[0].indices.size(), 100000u);
  EXPECT_GE(large->triangle_count(), 100000u);
}

TEST(Load, BuiltinPrefixAndUnknownNames) {
  Result<Scene> r = load_scene("builtin:cornell");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->source, "builtin:cornell");
  Result<Scene> bad = load_scene("builtin:nope");
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(bad.error().starts_with("builtin:nope: no such built-in scene")) << bad.error();
  EXPECT_NE(bad.error().find("cornell-spheres"), std::string::npos) << bad.error();  // lists the known ones
}

TEST(Load, ExtensionDecidesTheFormat) {
  std::string dir = std::string(PTVIEW_TEST_DATA) + "/good/";
  Result<Scene> obj = load_scene(dir + "quad_normals.obj");
  ASSERT_TRUE(obj.ok()) << obj.error();
  EXPECT_EQ(obj->meshes.size(), 1u);
  Result<Scene> json = load_scene(dir + "transformed.json");
  ASSERT_TRUE(json.ok()) << json.error();
  EXPECT_EQ(json->meshes.size(), 2u);
  // Both are finalized: a camera, and a light since neither has one.
  EXPECT_TRUE(obj->camera && json->camera);
  EXPECT_TRUE(obj->has_emitter() && json->has_emitter());
  Result<Scene> mtl = load_scene(dir + "materials.mtl");
  ASSERT_FALSE(mtl.ok());
  EXPECT_EQ(mtl.error(), dir + "materials.mtl: unsupported scene type '.mtl' (expected .json, .obj, .gltf or .glb)");
}

// The type is found from the extension; a file without one, and a missing file of an unknown type, say so.
TEST(Load, AFileWithoutATypeOrMissingSaysWhich) {
  test::TempDir dir;
  const std::string bare = dir.write("scene", "{}");
  Result<Scene> r = load_scene(bare);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), bare + ": unsupported scene type (no extension) (expected .json, .obj, .gltf or .glb)");
  Result<Scene> missing = load_scene(dir / "missing.xyz");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error(), dir / "missing.xyz" + ": cannot open: No such file or directory");
}

// A scene path that is not a regular file is refused before it is read: a device reads as nothing, and opening a
// FIFO for reading waits for a writer that never comes.
TEST(Load, WhatIsNotARegularFileIsRefusedUnread) {
  Result<Scene> dev = load_obj_scene("/dev/null");
  ASSERT_FALSE(dev.ok());
  EXPECT_EQ(dev.error(), "/dev/null: cannot open: not a regular file");
  test::TempDir dir;
  const std::string fifo = dir / "pipe.obj";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  Result<Scene> r = test::load_with_fifo_watchdog(fifo, [&] { return load_scene(fifo); });
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), fifo + ": cannot open: not a regular file");
}

// Materials of one name but different parameters are told apart by a numbered suffix on the first name: a#2, a#3,
// not a#2#3.
TEST(Load, SameNamedMaterialsAreNumberedFromTheirName) {
  Scene s;
  for (float r : {0.1f, 0.2f, 0.3f, 0.2f}) add_material(s, Material{"paint", MaterialType::diffuse, vec3(r)});
  ASSERT_EQ(s.materials.size(), 3u) << "the fourth is the second again";
  EXPECT_EQ(s.materials[0].name, "paint");
  EXPECT_EQ(s.materials[1].name, "paint#2");
  EXPECT_EQ(s.materials[2].name, "paint#3");
  // A glass does not read its albedo (an MTL's Kd sets it): two glasses that differ only there are one material.
  EXPECT_EQ(add_material(s, Material{"lens", MaterialType::glass, vec3(0.5f), 1.5f}),
            add_material(s, Material{"lens", MaterialType::glass, vec3(0.9f), 1.5f}));
}

// Every warning is one line, even one that quotes a file's text holding a line break (here a JSON key).
TEST(Load, WarningsAreOneLine) {
  test::TempDir dir;
  Result<Scene> r =
      load_scene(dir.write("s.json", R"({"shapes": [{"type": "sphere", "radius": 1}], "odd\nkey": 1, "odd\rone": 2})"));
  ASSERT_TRUE(r.ok()) << r.error();
  int unknown = 0;
  for (const std::string& w : r->warnings) {
    EXPECT_EQ(w.find_first_of("\n\r"), std::string::npos) << w;
    unknown += w.find("unknown key ignored") != std::string::npos;
  }
  EXPECT_EQ(unknown, 2);
}

}  // namespace
}  // namespace pt
