// OBJ/MTL loading: the material mapping rule by rule, triangulation keeping the winding, shading normals,
// degenerate triangles, relative indices, warnings with their lines; the MTL parser on its own; the bunny.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>

#include "scene/load.h"
#include "scene/mtl.h"
#include "scene/polygon.h"
#include "temp_dir.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

std::string good(const std::string& name) { return (fs::path(PTVIEW_TEST_DATA) / "good" / name).string(); }

const Material& face_material(const Scene& s, size_t face) { return s.materials[s.meshes.at(0).materials.at(face)]; }

vec3 face_normal(const Mesh& m, size_t t) {
  uvec3 i = m.indices[t];
  return glm::cross(m.positions[i.y] - m.positions[i.x], m.positions[i.z] - m.positions[i.x]);
}

void expect_vec3(vec3 actual, vec3 expected) {
  EXPECT_FLOAT_EQ(actual.x, expected.x);
  EXPECT_FLOAT_EQ(actual.y, expected.y);
  EXPECT_FLOAT_EQ(actual.z, expected.z);
}

Result<Scene> load_unfinalized(const std::string& name) {
  Result<Scene> r = load_obj_scene(good(name));
  EXPECT_TRUE(r.ok()) << r.error();
  return r;
}

TEST(LoadObj, MtlMappingRuleByRule) {
  Result<Scene> r = load_unfinalized("materials.obj");
  ASSERT_TRUE(r.ok());
  const Scene& s = *r;
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].indices.size(), 12u);
  auto expect = [&](size_t face, const char* name, MaterialType type, vec3 albedo, float ior = 1.5f) {
    SCOPED_TRACE(name);
    const Material& m = face_material(s, face);
    EXPECT_EQ(m.name, name);
    EXPECT_EQ(m.type, type);
    if (type == MaterialType::glass) {
      EXPECT_FLOAT_EQ(m.ior, ior);
    } else {
      expect_vec3(m.albedo, albedo);
    }
  };
  expect(0, "red", MaterialType::diffuse, vec3(0.8f, 0.1f, 0.1f));  // Kd; the later "red" is ignored
  expect(1, "light", MaterialType::diffuse, vec3(0.0f));
  expect_vec3(face_material(s, 1).emission, vec3(5, 4, 3));           // Ke
  expect(2, "mirror_illum", MaterialType::specular, vec3(0.9f, 0.8f, 0.7f));  // illum 3: albedo Ks
  expect(3, "mirror_ks", MaterialType::specular, vec3(0.9f));         // Ks dominant, Ns 1000
  expect(4, "glass_illum", MaterialType::glass, vec3(0), 1.33f);      // illum 7, Ni
  expect(5, "glass_d", MaterialType::glass, vec3(0), 1.7f);           // d < 1
  expect(6, "glass_tr", MaterialType::glass, vec3(0), 1.5f);          // Tr > 0, no Ni
  expect(7, "grey_single_kd", MaterialType::diffuse, vec3(0.25f));    // one Kd value is grey; Ns < 500
  expect(8, "mirror_wins_over_d", MaterialType::specular, vec3(0.6f));  // illum 5 before d < 1
  expect(9, "glass_no_ni", MaterialType::glass, vec3(0), 1.5f);       // illum 4, Ni 0 -> 1.5
  expect(10, "default", MaterialType::diffuse, vec3(0.8f));           // "usemtl" without a name
  EXPECT_EQ(s.meshes[0].materials[11], s.meshes[0].materials[0]);      // red again: the same material
  for (const Material& m : s.materials) EXPECT_EQ(m.emissive(), m.name == "light") << m.name;
  // Only used materials enter the scene, each once.
  EXPECT_EQ(s.materials.size(), 11u);
  for (const Material& m : s.materials) EXPECT_NE(m.name, "unused");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("materials.mtl:48: material 'red' defined again"), std::string::npos)
      << s.warnings[0];
}

TEST(LoadObj, FinalizedObjGetsACameraAndNoExtraLightWhenItEmits) {
  Result<Scene> r = load_scene(good("materials.obj"));
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(r->camera.has_value());
  EXPECT_TRUE(r->quads.empty());
}

TEST(LoadObj, QuadWithNormalsIsTwoFrontFacingTriangles) {
  Result<Scene> r = load_unfinalized("quad_normals.obj");
  ASSERT_TRUE(r.ok());
  const Mesh& m = r->meshes[0];
  EXPECT_EQ(m.name, good("quad_normals.obj"));
  ASSERT_EQ(m.indices.size(), 2u);
  ASSERT_EQ(m.normal_indices.size(), 2u);
  ASSERT_EQ(m.normals.size(), 1u);
  expect_vec3(m.normals[0], vec3(0, 0, 1));
  float area = 0.0f;
  for (size_t t = 0; t < 2; ++t) {
    vec3 n = face_normal(m, t);
    EXPECT_GT(n.z, 0.0f);  // counter-clockwise seen from +z: the front faces +z
    area += 0.5f * glm::length(n);
  }
  EXPECT_FLOAT_EQ(area, 1.0f);
  EXPECT_TRUE(r->warnings.empty());
}

TEST(LoadObj, ConcavePolygonsCrlfAndTrailingCommentsAreHandled) {
  Result<Scene> r = load_unfinalized("polygons.obj");
  ASSERT_TRUE(r.ok());
  const Mesh& m = r->meshes[0];
  ASSERT_EQ(m.indices.size(), 4u + 3u);  // a hexagon and a pentagon
  float area[2] = {0.0f, 0.0f};
  for (size_t t = 0; t < m.indices.size(); ++t) {
    vec3 n = face_normal(m, t);
    EXPECT_GT(n.z, 0.0f) << "triangle " << t << " flipped";
    EXPECT_NEAR(glm::length(vec2(n.x, n.y)), 0.0f, 1e-6f);
    area[m.positions[m.indices[t].x].z > 0.5f ? 1 : 0] += 0.5f * glm::length(n);
  }
  EXPECT_FLOAT_EQ(area[0], 3.0f);   // the L covers exactly its area: no overlap, nothing outside
  EXPECT_FLOAT_EQ(area[1], 1.25f);
  EXPECT_TRUE(m.normals.empty());
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_NE(r->warnings[0].find("polygons.obj:12: material 'nowhere' is not defined"), std::string::npos)
      << r->warnings[0];
}

TEST(LoadObj, FacesWithoutUsableNormalsShadeFlat) {
  Result<Scene> r = load_unfinalized("partial_normals.obj");
  ASSERT_TRUE(r.ok());
  const Mesh& m = r->meshes[0];
  ASSERT_EQ(m.indices.size(), 4u);
  ASSERT_EQ(m.normal_indices.size(), 4u);
  for (size_t t = 0; t < 4; ++t) {
    vec3 geometric = glm::normalize(face_normal(m, t));
    for (int k = 0; k < 3; ++k) {
      vec3 n = m.normals.at(m.normal_indices[t][k]);
      EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);          // "vn 0 0 2" normalized
      EXPECT_NEAR(glm::dot(n, geometric), 1.0f, 1e-6f);  // flat where the file gave none or a zero one
    }
  }
  EXPECT_EQ(m.normals.size(), 3u);  // the file's unit normal and two flat ones; the zero normal is gone
  EXPECT_EQ(m.positions.size(), 5u);
}

// A face shades with the file's normals only when all three of its corners have a usable one: a face whose second
// corner's normal is zero shades flat (all three corners), while the face beside it keeps the file's normal. And one
// dropped degenerate triangle is said in the singular.
TEST(LoadObj, AFaceWithOneUnusableCornerNormalShadesFlat) {
  test::TempDir dir;
  Result<Scene> r = load_obj_scene(dir.write("t.obj",
                                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\n"  // 1-5
                                             "vn 0.3 0 1\nvn 0 0 0\n"                         // 6-7
                                             "f 1//1 2//2 3//1\n"                             // 8
                                             "f 2//1 4//1 3//1\n"                             // 9
                                             "f 1 2 5\n"));                                   // 10: no area
  ASSERT_TRUE(r.ok()) << r.error();
  const Mesh& m = r->meshes[0];
  ASSERT_EQ(m.indices.size(), 2u);
  ASSERT_EQ(m.normal_indices.size(), 2u);
  const vec3 given = glm::normalize(vec3(0.3f, 0.0f, 1.0f));
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(m.normals.at(m.normal_indices[0][k]), vec3(0, 0, 1)) << "corner " << k << " of the first face";
    EXPECT_NEAR(glm::distance(m.normals.at(m.normal_indices[1][k]), given), 0.0f, 1e-6f) << "corner " << k;
  }
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_EQ(r->warnings[0],
            dir / "t.obj" + ":10: 1 degenerate (zero-area) triangle dropped (the first from this line)");
}

// Faces without a usemtl and faces naming materials no library defines all share one default grey material.
TEST(LoadObj, FacesWithoutAUsableMaterialShareOneDefaultGrey) {
  test::TempDir dir;
  dir.write("t.mtl", "newmtl red\nKd 1 0 0\n");
  Result<Scene> r = load_obj_scene(dir.write("t.obj",
                                             "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                             "f 1 2 3\nusemtl nowhere\nf 2 4 3\nusemtl red\nf 1 2 3\n"
                                             "usemtl elsewhere\nf 2 4 3\n"));
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->materials.size(), 2u) << "the default grey and red";
  EXPECT_EQ(r->warnings.size(), 2u) << "one for each undefined name";
  for (size_t face : {0, 1, 3}) {
    EXPECT_EQ(face_material(*r, face).name, "default") << "face " << face;
    EXPECT_EQ(r->meshes[0].materials[face], r->meshes[0].materials[0]) << "face " << face;
  }
  EXPECT_EQ(face_material(*r, 2).name, "red");
}

TEST(LoadObj, MissingMtlIsOneLocatedWarningAndDefaultGrey) {
  Result<Scene> r = load_unfinalized("missing_mtl.obj");
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->warnings.size(), 1u);  // not also one for its unknown usemtl
  EXPECT_TRUE(r->warnings[0].starts_with(good("missing_mtl.obj") + ":1: material library ")) << r->warnings[0];
  EXPECT_NE(r->warnings[0].find("nowhere.mtl: cannot open"), std::string::npos) << r->warnings[0];
  const Material& m = face_material(*r, 0);
  EXPECT_EQ(m.type, MaterialType::diffuse);
  expect_vec3(m.albedo, vec3(0.8f));
}

TEST(LoadObj, DegenerateTrianglesAreDroppedWithOneCountedWarning) {
  Result<Scene> r = load_unfinalized("with_degenerate.obj");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->meshes[0].indices.size(), 1u);
  EXPECT_EQ(r->meshes[0].positions.size(), 3u);  // the vertex only the dropped triangle used is gone too
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_EQ(r->warnings[0], good("with_degenerate.obj") + ":6: 3 degenerate (zero-area) triangles dropped (the first "
                                                          "from this line)");
}

TEST(LoadObj, TheFirstLibraryToDefineAMaterialWinsAndSaysSo) {
  Result<Scene> r = load_unfinalized("two_libraries.obj");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(face_material(*r, 0).name, "paint");
  expect_vec3(face_material(*r, 0).albedo, vec3(0.6f, 0.2f, 0.2f));  // libraries_first.mtl's, not the second's
  EXPECT_EQ(face_material(*r, 1).name, "trim");
  expect_vec3(face_material(*r, 1).albedo, vec3(0.1f, 0.5f, 0.1f));
  ASSERT_EQ(r->warnings.size(), 1u);
  EXPECT_EQ(r->warnings[0], good("two_libraries.obj") + ":3: material library " +
                                (fs::path(good("libraries_second.mtl"))).lexically_normal().string() +
                                " defines 'paint' again: the first definition is used");
}

TEST(LoadObj, OneMtllibMayNameSeveralLibrariesAndVtMayHaveOneNumber) {
  Result<Scene> r = load_unfinalized("libraries_one_line.obj");
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->meshes[0].indices.size(), 2u);
  EXPECT_EQ(face_material(*r, 0).name, "paint");
  expect_vec3(face_material(*r, 0).albedo, vec3(0.6f, 0.2f, 0.2f));  // the first library's
  EXPECT_EQ(face_material(*r, 1).name, "trim");                      // the second library's only material
  expect_vec3(face_material(*r, 1).albedo, vec3(0.1f, 0.5f, 0.1f));
  ASSERT_EQ(r->warnings.size(), 1u);  // 'paint' defined again, located at the one mtllib line
  EXPECT_NE(r->warnings[0].find("libraries_one_line.obj:3: material library"), std::string::npos) << r->warnings[0];
}

TEST(LoadObj, NegativeIndicesCountBackFromTheLastElement) {
  Result<Scene> r = load_unfinalized("negative_indices.obj");
  ASSERT_TRUE(r.ok());
  const Mesh& m = r->meshes[0];
  ASSERT_EQ(m.indices.size(), 1u);
  expect_vec3(m.positions[m.indices[0].x], vec3(0, 0, 0));
  expect_vec3(m.positions[m.indices[0].y], vec3(1, 0, 0));
  expect_vec3(m.positions[m.indices[0].z], vec3(0, 1, 0));
}

TEST(LoadObj, ABackslashAtALineEndContinuesTheLine) {
  // The OBJ specification's line continuation, after "\n", "\r\n" and a lone "\r"; Blender reads it the same way.
  test::TempDir dir;
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    const std::string text = "mtllib \\" + eol + "m.mtl" + eol +     // 1-2
                             "v 0 0 0" + eol + "v 1 \\" + eol +     // 3-4
                             "0 0" + eol + "v 0 1 0" + eol +         // 5-6
                             "usemtl red" + eol +                    // 7
                             "f 1 \\" + eol + "2 \\" + eol + "3" + eol +  // 8-10: one face over three lines
                             "# a comment \\" + eol + "f 1 2 3" + eol;    // 11-12: continued into the comment
    dir.write("m.mtl", "newmtl red\nKd 0.5 \\\n0.25 0.125\n");
    Result<Scene> r = load_obj_scene(dir.write("c.obj", text));
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_EQ(r->meshes.size(), 1u);
    const Mesh& m = r->meshes[0];
    ASSERT_EQ(m.indices.size(), 1u) << "a face in a continued comment is part of the comment";
    expect_vec3(m.positions[m.indices[0].y], vec3(1, 0, 0));
    EXPECT_EQ(face_material(*r, 0).name, "red");
    expect_vec3(face_material(*r, 0).albedo, vec3(0.5f, 0.25f, 0.125f));
    EXPECT_TRUE(r->warnings.empty()) << r->warnings[0];
  }
}

TEST(LoadObj, CommentsAfterATabAndPlusSignsAreRead) {
  // Exporters put a comment after a tab as often as after a space, and C's strtod (which most readers use) takes a
  // leading '+': both read as other readers read them, in the OBJ and in its MTL.
  test::TempDir dir;
  dir.write("t.mtl", "newmtl lamp\t# the light\nKd +0.25 0.5 +0.75\t# diffuse\nKe +1 2 +3\n");
  Result<Scene> r = load_obj_scene(dir.write(
      "t.obj", "mtllib t.mtl\t# library\nv +0 0 0\t# first\nv +1 0 -0\nv 0 +1 0\nusemtl lamp\t# light\nf 1 2 3\t# face\n"));
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->meshes.size(), 1u);
  const Mesh& m = r->meshes[0];
  ASSERT_EQ(m.indices.size(), 1u);
  expect_vec3(m.positions[m.indices[0].y], vec3(1, 0, 0));
  expect_vec3(m.positions[m.indices[0].z], vec3(0, 1, 0));
  EXPECT_EQ(face_material(*r, 0).name, "lamp");
  expect_vec3(face_material(*r, 0).albedo, vec3(0.25f, 0.5f, 0.75f));
  expect_vec3(face_material(*r, 0).emission, vec3(1, 2, 3));
  EXPECT_TRUE(r->warnings.empty()) << r->warnings[0];
}

TEST(LoadObj, LinesAfterAContinuedLineKeepTheirNumbers) {
  test::TempDir dir;
  const std::string head = "v 0 0 0\nv 1 \\\n0 0\nv 0 1 0\n";  // lines 1-4
  // An error in a joined line names its first line; one after it, its own.
  Result<Scene> inside = load_obj_scene(dir.write("a.obj", head + "f 1 2 \\\n9\n"));
  ASSERT_FALSE(inside.ok());
  EXPECT_TRUE(inside.error().ends_with("a.obj:5: face vertex index 9 out of range (3 defined so far)"))
      << inside.error();
  Result<Scene> after = load_obj_scene(dir.write("b.obj", head + "f 1 2 3\nf 1 2 \\\n3 \\\n\nf 1 2 x\n"));
  ASSERT_FALSE(after.ok());
  EXPECT_TRUE(after.error().ends_with("b.obj:9: face vertex index 'x' is not an integer")) << after.error();
  // A backslash elsewhere is not a continuation: still one located error.
  Result<Scene> inner = load_obj_scene(dir.write("c.obj", head + "f 1 \\ 2 3\n"));
  ASSERT_FALSE(inner.ok());
  EXPECT_TRUE(inner.error().ends_with("c.obj:5: face vertex index '\\' is not an integer")) << inner.error();
}

TEST(Mtl, MappingPrecedence) {
  MtlRecord r;
  r.kd = vec3(0.5f);
  EXPECT_EQ(material_from_mtl(r).type, MaterialType::diffuse);
  r.ks = vec3(0.6f);
  r.ns = 499.0f;
  EXPECT_EQ(material_from_mtl(r).type, MaterialType::diffuse);  // shiny enough only from Ns 500
  r.ns = 500.0f;
  EXPECT_EQ(material_from_mtl(r).type, MaterialType::specular);
  r.kd = vec3(0.7f);
  EXPECT_EQ(material_from_mtl(r).type, MaterialType::diffuse);  // Ks no longer dominant
  r.tr = 0.1f;
  EXPECT_EQ(material_from_mtl(r).type, MaterialType::glass);
  r.illum = 3;
  EXPECT_EQ(material_from_mtl(r).type, MaterialType::specular);  // an explicit mirror model wins
  r.illum = 6;
  r.ni = 1.0f;
  r.ke = vec3(2.0f);
  Material g = material_from_mtl(r);
  EXPECT_EQ(g.type, MaterialType::glass);
  EXPECT_FLOAT_EQ(g.ior, 1.0f);  // an explicit Ni 1 is kept
  EXPECT_TRUE(g.emissive());     // every type emits Ke
  r.ni = -2.0f;
  EXPECT_FLOAT_EQ(material_from_mtl(r).ior, 1.5f);
  EXPECT_EQ(material_from_mtl(MtlRecord{}).albedo, vec3(0.8f));  // no Kd: default grey
  // illum 6 alone (no d, no Tr) is glass; a Ks only as bright as Kd is not dominant, even at Ns 1000.
  MtlRecord six;
  six.illum = 6;
  EXPECT_EQ(material_from_mtl(six).type, MaterialType::glass);
  MtlRecord even;
  even.kd = vec3(0.5f);
  even.ks = vec3(0.5f);
  even.ns = 1000.0f;
  EXPECT_EQ(material_from_mtl(even).type, MaterialType::diffuse);
}

TEST(Mtl, ParsesValuesAndWarnsWithLines) {
  std::string text =
      "Kd 1 1 1\n"                         // 1: before any newmtl
      "newmtl  two words \t\n"             // 2: names keep inner spaces
      "Kd 1.5 0.5 0.5   # too bright\r\n"  // 3
      "Ke spectral file.spd\n"             // 4
      "map_Kd tex.png\n"                   // 5: not ours, accepted
      "newmtl b#1\n"                       // 6: '#' inside a word is not a comment
      "d -halo 0.25\n";                    // 7
  Result<MtlLibrary> r = parse_mtl(text, "x.mtl");
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->materials.size(), 2u);
  EXPECT_EQ(r->materials[0].name, "two words");
  expect_vec3(r->materials[0].albedo, vec3(1.5f, 0.5f, 0.5f));
  EXPECT_EQ(r->materials[1].name, "b#1");
  EXPECT_EQ(r->materials[1].type, MaterialType::glass);
  ASSERT_EQ(r->warnings.size(), 3u);
  EXPECT_TRUE(r->warnings[0].starts_with("x.mtl:1: 'Kd' before any newmtl")) << r->warnings[0];
  EXPECT_TRUE(r->warnings[1].starts_with("x.mtl:4: 'Ke spectral' is not supported")) << r->warnings[1];
  EXPECT_TRUE(r->warnings[2].starts_with("x.mtl:3: material 'two words': reflectance above 1")) << r->warnings[2];
}

// The energy warning names the line that set the reflectance the material uses: Ks for a mirror, Kd otherwise. A
// glass does not read its Kd, so a bright Kd there is not warned about.
TEST(Mtl, ReflectanceWarningNamesTheLineOfTheValueUsed) {
  std::string text =
      "newmtl mirror\n"  // 1
      "Kd 0.2\n"         // 2
      "Ks 1.2 1 1\n"     // 3
      "illum 3\n"        // 4
      "newmtl lens\n"    // 5
      "Kd 2\n"           // 6
      "illum 7\n"        // 7
      "newmtl plain\n"   // 8
      "illum 10\n";      // 9: the largest model number is accepted
  Result<MtlLibrary> r = parse_mtl(text, "x.mtl");
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->materials.size(), 3u);
  ASSERT_EQ(r->warnings.size(), 1u) << (r->warnings.empty() ? "" : r->warnings.back());
  EXPECT_TRUE(r->warnings[0].starts_with("x.mtl:3: material 'mirror': reflectance above 1")) << r->warnings[0];
}

TEST(Mtl, ErrorsNameTheirLine) {
  const std::pair<std::string, std::string> cases[] = {
      {"newmtl a\n\nKd 0.5 -0.1 0.5\n", "x.mtl:3: Kd must not be negative"},
      {"newmtl a\nKs 1 2\n", "x.mtl:2: Ks: expected 1 or 3 finite numbers"},
      {"newmtl a\nKe 1 nan 1\n", "x.mtl:2: Ke: expected 1 or 3 finite numbers"},
      {"newmtl a\nillum 2.5\n", "x.mtl:2: illum: expected an integer"},
      {"newmtl a\nillum 11\n", "x.mtl:2: illum: expected an integer from 0 to 10"},
      {"newmtl a\nNi\n", "x.mtl:2: Ni: expected a finite number"},
      {"newmtl a\nNs 1e99\n", "x.mtl:2: Ns: expected a finite number"},
      {"newmtl\n", "x.mtl:1: newmtl without a name"},
      {std::string("newmtl a\nKd 1\0 1 1\n", 19), "x.mtl:2: binary data"},
  };
  for (const auto& [text, expected] : cases) {
    Result<MtlLibrary> r = parse_mtl(text, "x.mtl");
    ASSERT_FALSE(r.ok()) << text;
    EXPECT_TRUE(r.error().starts_with(expected)) << r.error();
  }
}

/// Twice the signed area of a polygon in the xy plane (shoelace formula).
double shoelace(const std::vector<vec3>& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    vec3 u = p[i], v = p[(i + 1) % p.size()];
    a += double(u.x) * v.y - double(v.x) * u.y;
  }
  return a;
}

TEST(Polygon, TriangulationCoversConcavePolygonsWithTheirWinding) {
  // A comb with four teeth (concave, 12 corners), a star (10 corners), and both wound clockwise.
  std::vector<vec3> comb = {{0, 0, 0}, {7, 0, 0}, {7, 3, 0}, {6, 3, 0}, {6, 1, 0}, {5, 1, 0},
                            {5, 3, 0}, {2, 3, 0}, {2, 1, 0}, {1, 1, 0}, {1, 3, 0}, {0, 3, 0}};
  std::vector<vec3> star;
  for (int i = 0; i < 10; ++i) {
    float a = kTwoPi * i / 10, r = i % 2 ? 0.4f : 1.0f;
    star.push_back({r * std::cos(a), r * std::sin(a), 0.0f});
  }
  // A dart (a concave quad) whose inside diagonal, through the reflex corner (0, 1), is the longer one; from each of
  // its four corners, so that either diagonal is the inside one. And a rectangle with a corner in the middle of an
  // edge, which splits without a flat triangle.
  std::vector<std::vector<vec3>> polygons = {comb, star, {{0, 1, 0}, {1, 0, 0}, {0, 10, 0}, {-1, 0, 0}}};
  for (int start = 1; start < 4; ++start) {
    std::vector<vec3> dart = polygons.back();
    std::rotate(dart.begin(), dart.begin() + 1, dart.end());
    polygons.push_back(dart);
  }
  polygons.push_back({{1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}, {0, 0, 0}});  // the clipper's first corner is flat
  // A square with a square hole, joined by a bridge walked both ways (as exporters write a face with a hole): two
  // corners repeat the positions of two others, which must not keep the ears they touch from being clipped.
  polygons.push_back({{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {0, 0, 0}, {1, 1, 0}, {1, 3, 0}, {3, 3, 0},
                      {3, 1, 0}, {1, 1, 0}});
  for (std::vector<vec3> poly : polygons) {
    for (bool reversed : {false, true}) {
      if (reversed) std::reverse(poly.begin(), poly.end());
      std::vector<uvec3> tris;
      triangulate_polygon(poly, tris);
      ASSERT_EQ(tris.size(), poly.size() - 2);
      double total = 0.0, unsigned_total = 0.0;
      for (uvec3 t : tris) {
        double a = shoelace({poly[t.x], poly[t.y], poly[t.z]});
        EXPECT_GT(a * shoelace(poly), 0.0) << "a flat triangle or one against the polygon's winding";
        total += a;
        unsigned_total += std::abs(a);
      }
      EXPECT_NEAR(total, shoelace(poly), 1e-4);           // covers the polygon...
      EXPECT_NEAR(unsigned_total, std::abs(total), 1e-4);  // ...without overlaps
    }
  }
}

TEST(Polygon, WorksInAnyPlaneAndFallsBackToAFan) {
  // A concave hexagon rotated out of the xy plane keeps its area and faces along its Newell normal.
  std::vector<vec3> l = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  mat3 rot = glm::mat3_cast(glm::angleAxis(1.0f, glm::normalize(vec3(1, 2, 3))));
  for (vec3& p : l) p = rot * p + vec3(5, -3, 2);
  std::vector<uvec3> tris;
  triangulate_polygon(l, tris);
  ASSERT_EQ(tris.size(), 4u);
  vec3 expected_normal = rot * vec3(0, 0, 1);
  float area = 0.0f;
  for (uvec3 t : tris) {
    vec3 n = glm::cross(l[t.y] - l[t.x], l[t.z] - l[t.x]);
    EXPECT_GT(glm::dot(n, expected_normal), 0.0f);
    area += 0.5f * glm::length(n);
  }
  EXPECT_NEAR(area, 3.0f, 1e-4f);
  // Zero area (all corners on a line): still n - 2 triangles, all degenerate, for the caller to drop.
  std::vector<vec3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}};
  tris.clear();
  triangulate_polygon(line, tris);
  EXPECT_EQ(tris.size(), 3u);
  // Self-intersecting: a square with a loop out past its corner (0, 4). Clipping takes two ears and then finds none;
  // the whole polygon is then fanned, and the two ears are not kept beside the fan.
  std::vector<vec3> loop = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {6, 6, 0}, {6, 5, 0}};
  tris.clear();
  triangulate_polygon(loop, tris);
  std::vector<uvec3> fan = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
  EXPECT_EQ(tris, fan);
}

// Both diagonals of a convex quad are inside it; the shorter one gives the better-shaped pair (a long thin rhombus
// split along its long diagonal gives two slivers).
TEST(Polygon, AConvexQuadSplitsAlongItsShorterDiagonal) {
  std::vector<vec3> rhombus = {{-5, 0, 0}, {0, -1, 0}, {5, 0, 0}, {0, 1, 0}};
  for (int start = 0; start < 2; ++start) {
    std::vector<uvec3> tris;
    triangulate_polygon(rhombus, tris);
    ASSERT_EQ(tris.size(), 2u);
    // The short diagonal joins the corners at y = +-1: both triangles have both of them.
    for (uvec3 t : tris) {
      int on_short = 0;
      for (uint32_t i : {t.x, t.y, t.z}) on_short += std::abs(rhombus[i].y) == 1.0f;
      EXPECT_EQ(on_short, 2) << "start " << start;
    }
    std::rotate(rhombus.begin(), rhombus.begin() + 1, rhombus.end());
  }
}

TEST(LoadObj, BunnyLoadsWhenPresent) {
  fs::path bunny = fs::path(PTVIEW_SOURCE_DIR) / ".." / "shared" / "models" / "stanford-bunny.obj";
  if (!fs::exists(bunny)) GTEST_SKIP() << "no " << bunny;
  auto start = std::chrono::steady_clock::now();
  Result<Scene> r = load_scene(bunny.string());
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->meshes.size(), 1u);
  EXPECT_EQ(r->meshes[0].indices.size(), 69451u);
  RecordProperty("seconds", std::to_string(seconds));  // recorded, never asserted: machines are shared
  EXPECT_TRUE(r->camera.has_value());
  EXPECT_EQ(r->quads.size(), 1u);  // the default light
}

}  // namespace
}  // namespace pt
