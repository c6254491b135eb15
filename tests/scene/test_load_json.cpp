// Scene JSON: transforms (positions, normals, winding under mirroring), the generated mesh, defaults, material
// references and naming, warnings with their lines, and errors that never escape as exceptions.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>

#include "scene/load.h"
#include "scene/procedural.h"
#include "temp_dir.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

std::string good(const std::string& name) { return (fs::path(PTVIEW_TEST_DATA) / "good" / name).string(); }

bool has_warning(const Scene& s, const std::string& text) {
  for (const std::string& w : s.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

vec3 geometric_normal(const Mesh& m, size_t t) {
  uvec3 i = m.indices[t];
  return glm::normalize(glm::cross(m.positions[i.y] - m.positions[i.x], m.positions[i.z] - m.positions[i.x]));
}

using test::TempDir;  // a scratch folder for scenes that need files beside them

Result<Scene> parse(const std::string& text, const std::string& path = "inline.json") {
  return parse_json_scene(text, path);
}

TEST(LoadJson, TransformsScaleThenRotateThenTranslate) {
  Result<Scene> r = load_scene(good("transformed.json"));
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->meshes.size(), 2u);
  const Mesh& m = r->meshes[0];
  // The unit quad's corners scaled by 2, rotated 90 degrees about +z ((x, y) -> (-y, x)), moved by +10 in x.
  std::vector<vec3> expected = {{10, 0, 0}, {10, 2, 0}, {8, 2, 0}, {8, 0, 0}};
  ASSERT_EQ(m.positions.size(), 4u);
  for (vec3 e : expected) {
    float nearest = 1e9f;
    for (uint32_t i = 0; i < m.positions.size(); ++i) nearest = std::min(nearest, glm::length(m.world_position(i) - e));
    EXPECT_LT(nearest, 1e-5f) << e.x << " " << e.y << " " << e.z;
  }
  for (uint32_t id : m.materials) EXPECT_EQ(r->materials[id].name, "m");  // the override, on every face
  // The mirrored copy: x negated, and the front still faces +z like the file's counter-clockwise quad.
  const Mesh& mirrored = r->meshes[1];
  for (uint32_t i = 0; i < mirrored.positions.size(); ++i) EXPECT_LE(mirrored.world_position(i).x, 0.0f);
  for (size_t t = 0; t < mirrored.indices.size(); ++t) {
    EXPECT_GT(geometric_normal(mirrored, t).z, 0.99f);
    for (int k = 0; k < 3; ++k) EXPECT_GT(mirrored.normals[mirrored.normal_indices[t][k]].z, 0.99f);
  }
  for (uint32_t id : mirrored.materials) EXPECT_EQ(r->materials[id].name, "default");
}

TEST(LoadJson, NormalsFollowTheInverseTransposeUnderEveryTransform) {
  // A sloped triangle whose vn is its true normal: after any transform the shading normal must still be the
  // (unit) geometric normal, which fails if normals were transformed like positions or the winding not fixed.
  TempDir dir;
  dir.write("slope.obj", "v 0 0 0\nv 1 0 0\nv 0 1 1\nvn 0 -0.7071068 0.7071068\nf 1//1 2//1 3//1\n");
  const char* transforms[] = {
      R"({"scale": [1, 3, 0.5]})",
      R"({"scale": [-1, 2, 1], "rotate": [1, 1, 0, 30]})",
      R"({"scale": -2, "rotate": [0, 0, 5, -70], "translate": [1, 2, 3]})",
      R"({"scale": [2, -1, -0.5], "rotate": [3, -1, 2, 200]})",
  };
  for (const char* t : transforms) {
    SCOPED_TRACE(t);
    std::string path = dir.write(
        "scene.json", std::string(R"({"shapes": [{"type": "mesh", "file": "slope.obj", "transform": )") + t + "}]}");
    Result<Scene> r = load_scene(path);
    ASSERT_TRUE(r.ok()) << r.error();
    const Mesh& m = r->meshes.at(0);
    vec3 ng = geometric_normal(m, 0);
    for (int k = 0; k < 3; ++k) {
      vec3 n = m.normals[m.normal_indices[0][k]];
      EXPECT_NEAR(glm::dot(n, ng), 1.0f, 1e-5f);
    }
  }
}

TEST(LoadJson, ATranslationUpTo1e6KeepsTheMeshShapeExact) {
  // Issue 13: positions transformed in float and stored in world space snap to the float grid there (1/16 at
  // 1e6), which folds small triangles. The mesh keeps its origin in double and its positions relative to it.
  TempDir dir;
  dir.write("tri.obj", "v 0.001 0.002 0.003\nv 0.0123 0 0\nv 0 0.0456 0.0001\nf 1 2 3\n");
  for (double offset : {1e5, 1e6}) {
    std::string path = dir.write("scene.json", R"({"shapes": [{"type": "mesh", "file": "tri.obj", "transform":
        {"rotate": [0, 0, 1, 90], "translate": [)" + std::to_string(offset) + ", " + std::to_string(-offset) + ", " +
                                                   std::to_string(offset) + "]}}]}");
    Result<Scene> r = load_scene(path);
    ASSERT_TRUE(r.ok()) << r.error();
    const Mesh& m = r->meshes[0];
    // Rotation by 90 degrees about z: (x, y, z) -> (-y, x, z).
    const dvec3 expected[3] = {{-0.002, 0.001, 0.003}, {0, 0.0123, 0}, {-0.0456, 0, 0.0001}};
    for (int k = 0; k < 3; ++k) {
      dvec3 relative = m.origin + dvec3(m.positions[m.indices[0][k]]) - dvec3(offset, -offset, offset);
      EXPECT_LT(glm::length(relative - expected[k]), 1e-8) << offset << " corner " << k;
    }
  }
}

TEST(LoadJson, RotationIsRightHandedAboutANormalizedAxis) {
  TempDir dir;
  dir.write("tri.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  // 120 degrees about (1, 1, 1) (any length) cycles the axes: x -> y -> z -> x.
  std::string path = dir.write(
      "scene.json", R"({"shapes": [{"type": "mesh", "file": "tri.obj", "transform": {"rotate": [2, 2, 2, 120]}}]})");
  Result<Scene> r = load_scene(path);
  ASSERT_TRUE(r.ok()) << r.error();
  const Mesh& m = r->meshes[0];
  vec3 expected[3] = {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
  for (int k = 0; k < 3; ++k) EXPECT_LT(glm::length(m.world_position(m.indices[0][k]) - expected[k]), 1e-5f);
}

TEST(LoadJson, GeneratedKnotKeepsItsOutsideUnderAMirroringTransform) {
  Result<Scene> r = load_scene(good("generated.json"));
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->meshes.size(), 1u);
  const Mesh& m = r->meshes[0];
  EXPECT_EQ(m.indices.size(), size_t(2 * 96 * 12));
  EXPECT_GT(signed_volume(m), 0.0);  // scale z by -1 mirrors it: the winding was swapped back
  size_t inward = 0;
  for (size_t t = 0; t < m.indices.size(); ++t)
    if (glm::dot(geometric_normal(m, t), m.normals[m.normal_indices[t].x]) <= 0.0f) ++inward;
  EXPECT_EQ(inward, 0u);
  // Laid flat by the rotation: its symmetry axis is now y, so it is thin in y around the translation.
  AABB b;  // of the mesh alone (the scene also has the default light above it)
  for (uint32_t i = 0; i < m.positions.size(); ++i) b.extend(m.world_position(i));
  EXPECT_NEAR(b.center().y, 0.5f, 0.02f);
  EXPECT_LT(b.extent().y, 1.45f);
  EXPECT_GT(b.extent().x, 3.0f);
  EXPECT_EQ(r->materials[m.materials[0]].name, "default");
}

TEST(LoadJson, DefaultsAndSharedDefaultMaterial) {
  Result<Scene> r = parse(R"({
    "version": 1.0,
    "camera": {"fov": 55},
    "materials": {"plain": {}, "glassy": {"type": "glass"}},
    "shapes": [
      {"type": "sphere", "radius": 2},
      {"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0]},
      {"type": "sphere", "center": [1, 2, 3], "radius": 0.5, "material": "glassy"}
    ]})");
  ASSERT_TRUE(r.ok()) << r.error();
  const Scene& s = *r;
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->eye, Camera{}.eye);
  EXPECT_EQ(s.camera->up, Camera{}.up);
  EXPECT_FLOAT_EQ(s.camera->fov_deg, 55.0f);
  EXPECT_FALSE(s.background.has_value());
  // Material order is the file's; defaults: diffuse, albedo 0.8, ior 1.5, no emission.
  ASSERT_GE(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "plain");
  EXPECT_EQ(s.materials[1].name, "glassy");
  EXPECT_EQ(s.materials[0].type, MaterialType::diffuse);
  EXPECT_EQ(s.materials[0].albedo, vec3(0.8f));
  EXPECT_FALSE(s.materials[0].emissive());
  EXPECT_EQ(s.materials[1].type, MaterialType::glass);
  EXPECT_FLOAT_EQ(s.materials[1].ior, 1.5f);
  // Shapes without a material share one "default", created once; sphere center defaults to the origin.
  ASSERT_EQ(s.spheres.size(), 2u);
  ASSERT_EQ(s.quads.size(), 1u);
  EXPECT_EQ(s.spheres[0].center, vec3(0.0f));
  EXPECT_EQ(s.spheres[0].material, s.quads[0].material);
  EXPECT_EQ(s.materials[s.spheres[0].material].name, "default");
  EXPECT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[s.spheres[1].material].name, "glassy");
  EXPECT_TRUE(s.warnings.empty());
}

TEST(LoadJson, EmptyShapesIsAnEmptySceneThatFinalizeLights) {
  Result<Scene> r = parse(R"({"shapes": []})");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->triangle_count(), 0u);
  EXPECT_TRUE(r->spheres.empty());
  finalize_scene(*r);
  EXPECT_TRUE(r->camera.has_value());
  EXPECT_TRUE(r->has_emitter());
}

TEST(LoadJson, WarningsCarryTheirLines) {
  std::string text =
      "{\n"                                                                             // 1
      "  \"extra\": 1,\n"                                                               // 2
      "  \"camera\": {\"eye\": [0, 0, 3], \"lookat\": [0, 0, 0]},\n"                    // 3
      "  \"materials\": {\n"                                                            // 4
      "    \"bright\": {\"albedo\": [1.2, 0.5, 0.5], \"roughness\": 0.1}\n"              // 5
      "  },\n"                                                                          // 6
      "  \"shapes\": [\n"                                                               // 7
      "    {\"type\": \"sphere\", \"radius\": 1, \"materail\": \"x\"},\n"               // 8
      "    {\"type\": \"quad\", \"corner\": [0, 0, 0], \"edge1\": [1, 0, 0],\n"         // 9
      "     \"edge2\": [2, 0, 0]},\n"                                                   // 10
      "    {\"type\": \"mesh\", \"generate\": {\"kind\": \"torus-knot\", \"segments\": 8, \"sides\": 3,\n"  // 11
      "      \"colour\": 1},\n"                                                         // 12
      "     \"transform\": {\"shift\": [1, 0, 0]}}\n"                                   // 13
      "  ]\n"                                                                           // 14
      "}\n";
  Result<Scene> r = parse(text, "w.json");
  ASSERT_TRUE(r.ok()) << r.error();
  std::vector<std::string> expected = {
      "w.json:2: extra: unknown key ignored",
      "w.json:3: camera.lookat: unknown key ignored",
      "w.json:5: materials.bright.roughness: unknown key ignored",
      "w.json:5: materials.bright.albedo: albedo above 1 does not conserve energy",
      "w.json:8: shapes[0].materail: unknown key ignored",
      "w.json:9: shapes[1]: quad has zero area: skipped",
      "w.json:12: shapes[2].generate.colour: unknown key ignored",
      "w.json:13: shapes[2].transform.shift: unknown key ignored",
  };
  std::vector<std::string> got = r->warnings;
  std::sort(got.begin(), got.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(got, expected);
  EXPECT_TRUE(r->quads.empty());  // the zero-area quad was skipped
  EXPECT_EQ(r->meshes.size(), 1u);
}

TEST(LoadJson, TinyAndHugeQuadsAndCamerasAreNotTakenForDegenerateOnes) {
  // Float squares of lengths vanish below about 1e-19 and overflow above 1e19: the checks are in double, so a quad
  // 1e-15 or 1e15 across is a quad, and a camera at such scales is a camera (RenderGeometry::scale renders them).
  for (const char* s : {"1e-15", "1e15", "1e-30", "1e30"}) {
    const std::string v = s;
    const std::string text = "{\"camera\": {\"eye\": [0, 0, " + v + "], \"target\": [0, 0, 0]},\n"
                             " \"shapes\": [{\"type\": \"quad\", \"corner\": [0, 0, 0], \"edge1\": [" + v +
                             ", 0, 0], \"edge2\": [0, " + v + ", 0]}]}";
    Result<Scene> r = parse(text, "s.json");
    ASSERT_TRUE(r.ok()) << s << ": " << r.error();
    EXPECT_EQ(r->quads.size(), 1u) << s;
    EXPECT_TRUE(r->warnings.empty()) << s << ": " << r->warnings[0];
  }
  Result<Scene> huge = parse(
      "{\"shapes\": [\n{\"type\": \"quad\", \"corner\": [3e38, 0, 0], \"edge1\": [3e38, 0, 0], \"edge2\": [0, 1, 0]}]}",
      "h.json");
  ASSERT_FALSE(huge.ok());
  EXPECT_EQ(huge.error(), "h.json:2: shapes[0]: quad too large (its far corner is beyond float's range)");
}

TEST(LoadJson, ManyWarningsAreCappedAndCounted) {
  std::string text = "{\"shapes\": [\n";
  const int n = 20000;
  for (int i = 0; i < n; ++i)
    text += std::string(i ? "," : "") + "{\"type\": \"sphere\", \"radius\": 1, \"colour\": 2}\n";
  text += "]}";
  auto start = std::chrono::steady_clock::now();
  Result<Scene> r = parse(text, "many.json");
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->spheres.size(), size_t(n));
  ASSERT_EQ(r->warnings.size(), 101u);
  EXPECT_EQ(r->warnings[0], "many.json:2: shapes[0].colour: unknown key ignored");
  EXPECT_EQ(r->warnings[99], "many.json:101: shapes[99].colour: unknown key ignored");
  EXPECT_EQ(r->warnings[100], "many.json: " + std::to_string(n - 100) + " more warnings not shown");
  RecordProperty("seconds", std::to_string(seconds));  // timing is a benchmark's job, not a test's
}

TEST(LoadJson, BackgroundMeansNoDefaultLight) {
  Result<Scene> r = load_scene(good("typo_key.json"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(has_warning(*r, "typo_key.json:4: shapes[0].materail: unknown key ignored"));
  ASSERT_TRUE(r->background.has_value());
  EXPECT_EQ(*r->background, vec3(1.0f));
  EXPECT_TRUE(r->quads.empty());
  EXPECT_FALSE(has_warning(*r, "default rectangle light"));
}

TEST(LoadJson, MaterialOverrideNeedsNoMtlAndOthersDo) {
  TempDir dir;
  std::string missing = good("missing_mtl.obj");
  std::string with = dir.write("a.json", R"({"materials": {"m": {}}, "shapes": [{"type": "mesh", "file": ")" + missing +
                                             R"(", "material": "m"}]})");
  Result<Scene> r = load_scene(with);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_FALSE(has_warning(*r, "nowhere.mtl"));  // absolute path, override: the .mtl is not looked at
  std::string without = dir.write("b.json", R"({"shapes": [{"type": "mesh", "file": ")" + missing + R"("}]})");
  r = load_scene(without);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(has_warning(*r, "missing_mtl.obj:1: material library"));
}

TEST(LoadJson, MaterialNamesStayUnique) {
  TempDir dir;
  dir.write("a.mtl", "newmtl red\nKd 1 0 0\nnewmtl default\nKd 0.8 0.8 0.8\n");
  dir.write("a.obj",
            "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\nusemtl default\nf 1 3 2\nf 2 3 1\n");
  std::string path = dir.write("s.json", R"({
    "materials": {"red": {"albedo": [0.5, 0, 0]}},
    "shapes": [{"type": "mesh", "file": "a.obj"}, {"type": "mesh", "file": "a.obj"},
               {"type": "sphere", "radius": 1}]})");
  Result<Scene> r = load_scene(path);
  ASSERT_TRUE(r.ok()) << r.error();
  std::map<std::string, int> names;
  for (const Material& m : r->materials) names[m.name]++;
  for (const auto& [name, count] : names) EXPECT_EQ(count, 1) << name;
  // The JSON's red keeps its name; the OBJ's different red is renamed; the second copy of the OBJ shares the
  // first's materials; the OBJ's "default" equals the sphere's default grey and is shared too.
  EXPECT_EQ(r->materials[0].name, "red");
  EXPECT_EQ(r->materials[r->meshes[0].materials[0]].name, "red#2");
  EXPECT_EQ(r->materials[r->meshes[0].materials[0]].albedo, vec3(1, 0, 0));
  EXPECT_EQ(r->meshes[0].materials, r->meshes[1].materials);
  EXPECT_EQ(r->materials[r->meshes[0].materials[1]].name, "default");
  EXPECT_EQ(r->meshes[0].materials[1], r->spheres[0].material);
  EXPECT_EQ(names.size(), 4u);  // red, red#2, default, and the default light's material
}

TEST(LoadJson, MaterialsOfOneNameThatDifferInAnyParameterStayApart) {
  // The first three OBJ materials below have the names of JSON materials and differ from them in one parameter
  // that renders: emission, ior or type. Each must be a material of its own (renamed), never merged into the
  // JSON's. The fourth differs only in what its type does not read (a glass's albedo, from Kd): it is the same
  // material, and shares the JSON's.
  TempDir dir;
  dir.write("a.mtl",
            "newmtl lamp\nKd 0.5 0.5 0.5\nnewmtl lens\nillum 4\nNi 1.33\nnewmtl shiny\nillum 3\nKd 0 0 0\n"
            "Ks 0.5 0.5 0.5\nnewmtl clear\nillum 4\nKd 0.3 0.3 0.3\nNi 1.5\n");
  dir.write("a.obj",
            "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\nusemtl lens\nf 1 3 2\n"
            "usemtl shiny\nf 2 3 1\nusemtl clear\nf 3 1 2\n");
  std::string path = dir.write("s.json", R"({
    "materials": {"lamp": {"albedo": [0.5, 0.5, 0.5], "emission": [2, 2, 2]}, "lens": {"type": "glass", "ior": 1.5},
                  "shiny": {"albedo": [0.5, 0.5, 0.5]}, "clear": {"type": "glass", "ior": 1.5}},
    "shapes": [{"type": "mesh", "file": "a.obj"}]})");
  Result<Scene> r = load_scene(path);
  ASSERT_TRUE(r.ok()) << r.error();
  const std::vector<uint32_t>& used = r->meshes[0].materials;
  ASSERT_EQ(used.size(), 4u);
  EXPECT_EQ(r->materials[used[3]].name, "clear");
  const Material &lamp = r->materials[used[0]], &lens = r->materials[used[1]], &shiny = r->materials[used[2]];
  EXPECT_EQ(lamp.name, "lamp#2");
  EXPECT_EQ(lamp.emission, vec3(0.0f));
  EXPECT_EQ(lens.name, "lens#2");
  EXPECT_FLOAT_EQ(lens.ior, 1.33f);
  EXPECT_EQ(shiny.name, "shiny#2");
  EXPECT_EQ(shiny.type, MaterialType::specular);
}

TEST(LoadJson, SyntaxErrorsGiveLineAndColumn) {
  Result<Scene> r = parse("{\n  \"shapes\": [\n    {\"type\": \"sphere\",, \"radius\": 1}\n  ]\n}", "s.json");
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.error().starts_with("s.json:3: invalid JSON (column 23): syntax error")) << r.error();
}

TEST(LoadJson, ARepeatedKeyIsReportedWhereItsValueIsUsed) {
  // JSON leaves repeated keys to the parser; nlohmann takes the last value, so the error names that one's line.
  Result<Scene> r = parse("{\"camera\": {\"eye\": [0, 0, 5], \"target\": [0, 0, 0],\n \"fov\": 30,\n \"fov\": 200},\n"
                          "\"shapes\": []}", "dup.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "dup.json:3: camera.fov: fov must be between 0 and 180 degrees (exclusive)");
}

TEST(LoadJson, AcceptsAByteOrderMarkAndLocatesAfterIt) {
  Result<Scene> r = parse("\xEF\xBB\xBF{\n\"shapes\": [\n{\"type\": \"sphere\", \"radius\": -1}]}", "bom.json");
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.error().starts_with("bom.json:3: shapes[0].radius: radius must be positive")) << r.error();
}

TEST(LoadJson, NamesWithControlCharactersKeepMessagesOnOneLine) {
  Result<Scene> r = parse("{\"shapes\": [], \"a\\nb\": 1}", "c.json");
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_EQ(r->warnings[0], "c.json:1: a\\nb: unknown key ignored");
  r = parse("{\"shapes\": [{\"type\": \"sphere\", \"radius\": 1, \"material\": \"x\\ny\\u0001\"}]}", "c.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "c.json:1: shapes[0].material: unknown material 'x\\ny\\x01'");
}

TEST(LoadJson, HostileInputIsAnErrorNotACrash) {
  // Deep nesting, a huge exponent, wrong types where objects are expected: one error each, never an exception.
  const std::string deep = "{\"x\": " + std::string(200000, '[') + std::string(200000, ']') + "}";
  const std::string cases[] = {deep, "{\"shapes\": [1e400]}", "{\"shapes\": [null]}", "{\"shapes\": [[]]}",
                               "{\"materials\": {\"a\": 1}, \"shapes\": []}", "{\"shapes\": [], \"camera\": null}",
                               "\"just a string\"", "{\"shapes\": [{\"type\": 5}]}",
                               "{\"shapes\": [{\"type\": \"mesh\", \"generate\": {\"kind\": \"torus-knot\", "
                               "\"segments\": 100000, \"sides\": 4096}}]}"};
  for (const std::string& text : cases) {
    Result<Scene> r = Error{""};
    EXPECT_NO_THROW(r = parse(text, "h.json")) << text.substr(0, 60);
    ASSERT_FALSE(r.ok()) << text.substr(0, 60);
    EXPECT_TRUE(r.error().starts_with("h.json:1: ")) << r.error();
  }
}

}  // namespace
}  // namespace pt
