// glTF 2.0 loading: geometry (indices, interleaving, strips, sparse), node transforms, cameras, the material
// mapping, .glb, glTF inside scene JSON, and every kind of bad input as one "FILE: reason" line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <stb_image_write.h>

#include "gltf_fixture.h"
#include "scene/load.h"
#include "temp_dir.h"

namespace pt {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::GltfBuilder;

using test::TempDir;

const std::vector<vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

Scene load_ok(const std::string& path) {
  Result<Scene> r = load_scene(path);
  EXPECT_TRUE(r.ok()) << r.error();
  return r.ok() ? std::move(*r) : Scene{};
}

std::string load_error(const std::string& path) {
  Result<Scene> r = load_scene(path);
  EXPECT_FALSE(r.ok()) << path << " loaded";
  if (r.ok()) return "";
  EXPECT_EQ(r.error().find('\n'), std::string::npos);
  EXPECT_TRUE(r.error().starts_with(path + ":")) << r.error();
  return r.error();
}

/// Bounds of the meshes only (finalize_scene may add a default light above them).
AABB mesh_bounds(const Scene& s) {
  AABB b;
  for (const Mesh& m : s.meshes)
    for (uvec3 t : m.indices)
      for (int k = 0; k < 3; ++k) b.extend(m.positions[t[k]]);
  return b;
}

bool has_warning(const Scene& s, const std::string& piece) {
  for (const std::string& w : s.warnings)
    if (w.find(piece) != std::string::npos) return true;
  return false;
}

TEST(Gltf, EmbeddedTriangle) {
  TempDir dir;
  GltfBuilder b;
  b.node({{"mesh", b.mesh(b.positions(kTriangle))}});
  test::write_file(dir / "t.gltf", b.embedded());
  Scene s = load_ok(dir / "t.gltf");
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].indices.size(), 1u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(s.meshes[0].positions[s.meshes[0].indices[0][k]], kTriangle[size_t(k)]);
  EXPECT_EQ(s.materials[s.meshes[0].materials[0]].name, "default");
  EXPECT_TRUE(s.meshes[0].normals.empty());
}

template <class T>
void box_with_indices() {
  TempDir dir;
  std::vector<vec3> p;
  for (int i = 0; i < 8; ++i) p.push_back(vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  std::vector<T> idx = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                        2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  GltfBuilder b;
  b.node({{"mesh", b.mesh(b.positions(p), b.indices(idx))}});
  test::write_file(dir / "box.gltf", b.embedded());
  Scene s = load_ok(dir / "box.gltf");
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.indices.size(), 12u);
  for (size_t t = 0; t < 12; ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.positions[m.indices[t][k]], p[idx[3 * t + size_t(k)]]);
  EXPECT_EQ(mesh_bounds(s).lo, vec3(-1.0f));
  EXPECT_EQ(mesh_bounds(s).hi, vec3(1.0f));
}
TEST(Gltf, BoxWithUnsignedByteIndices) { box_with_indices<uint8_t>(); }
TEST(Gltf, BoxWithUnsignedShortIndices) { box_with_indices<uint16_t>(); }
TEST(Gltf, BoxWithUnsignedIntIndices) { box_with_indices<uint32_t>(); }

TEST(Gltf, InterleavedPositionsAndNormals) {
  TempDir dir;
  // position, normal, position, normal, ... in one view with a 24-byte stride.
  std::vector<vec3> data;
  vec3 normals[3] = {{0, 0, 1}, {0, 0.6f, 0.8f}, {0.6f, 0, 0.8f}};
  for (int i = 0; i < 3; ++i) {
    data.push_back(kTriangle[size_t(i)]);
    data.push_back(normals[i]);
  }
  GltfBuilder b;
  int v = b.view(data.data(), data.size() * 12, 24);
  int pos = b.accessor(v, 0, 5126, 3, "VEC3"), nrm = b.accessor(v, 12, 5126, 3, "VEC3");
  b.node({{"mesh", b.mesh(pos, -1, -1, nrm)}});
  test::write_file(dir / "i.gltf", b.embedded());
  Scene s = load_ok(dir / "i.gltf");
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.indices.size(), 1u);
  ASSERT_EQ(m.normal_indices.size(), 1u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(m.positions[m.indices[0][k]], kTriangle[size_t(k)]);
    EXPECT_NEAR(glm::distance(m.normals[m.normal_indices[0][k]], normals[k]), 0.0f, 1e-6f);
  }
}

TEST(Gltf, QuantizedPositionsAndNormals) {
  // KHR_mesh_quantization (gltfpack's default output): positions as normalized or plain integers, scaled back by the
  // node's transform; normals as normalized bytes. Elements padded to 4 bytes, as the extension requires.
  TempDir dir;
  GltfBuilder b;
  auto quantized = [&](const void* data, size_t bytes, size_t stride, int component, bool normalized) {
    int acc = b.accessor(b.view(data, bytes, stride), 0, component, 3, "VEC3");
    b.j["accessors"][size_t(acc)]["normalized"] = normalized;
    return acc;
  };
  const uint16_t u16[12] = {0, 0, 0, 0, 65535, 0, 0, 0, 0, 65535, 0, 0};  // normalized: 0 and 1
  const int8_t n8[12] = {0, 0, 127, 0, 0, 0, 127, 0, 0, -128, 0, 0};      // normalized: (0, 0, 1), (0, -1, 0)
  b.node({{"mesh", b.mesh(quantized(u16, sizeof u16, 8, 5123, true), -1, -1, quantized(n8, sizeof n8, 4, 5120, true))},
          {"scale", {2, 2, 2}}});
  const int16_t s16[12] = {-3, 0, 0, 0, 5, 0, 0, 0, 0, 7, 0, 0};  // plain integers: their values
  b.node({{"mesh", b.mesh(quantized(s16, sizeof s16, 8, 5122, false))}, {"translation", {0, 0, -1}}});
  const int8_t s8[12] = {-128, 0, 0, 0, 127, 0, 0, 0, 0, 127, 0, 0};  // normalized: -1 (clamped from -128/127), 1
  b.node({{"mesh", b.mesh(quantized(s8, sizeof s8, 4, 5120, true))}, {"translation", {0, 0, -2}}});
  const uint8_t u8[12] = {0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0, 0};  // normalized: 0 and 1 (255 / 255)
  b.node({{"mesh", b.mesh(quantized(u8, sizeof u8, 4, 5121, true))}, {"translation", {0, 0, -3}}});
  const int16_t n16[12] = {-32768, 0, 0, 0, 32767, 0, 0, 0, 0, 32767, 0, 0};  // normalized: -1 (clamped), 1
  b.node({{"mesh", b.mesh(quantized(n16, sizeof n16, 8, 5122, true))}, {"translation", {0, 0, -4}}});
  const uint16_t p16[12] = {0, 0, 0, 0, 9, 0, 0, 0, 0, 11, 0, 0};  // plain unsigned shorts: their values
  b.node({{"mesh", b.mesh(quantized(p16, sizeof p16, 8, 5123, false))}, {"translation", {0, 0, -5}}});
  b.j["extensionsUsed"] = b.j["extensionsRequired"] = {"KHR_mesh_quantization"};
  test::write_file(dir / "q.gltf", b.embedded());
  Scene s = load_ok(dir / "q.gltf");
  ASSERT_EQ(s.meshes.size(), 1u);
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.indices.size(), 6u);
  std::vector<vec3> corners;
  for (uvec3 t : m.indices)
    for (int k = 0; k < 3; ++k) corners.push_back(vec3(m.origin + dvec3(m.positions[t[k]])));
  const std::vector<vec3> want = {{0, 0, 0},   {2, 0, 0},  {0, 2, 0},  {-3, 0, -1}, {5, 0, -1}, {0, 7, -1},
                                  {-1, 0, -2}, {1, 0, -2}, {0, 1, -2}, {0, 0, -3},  {1, 0, -3}, {0, 1, -3},
                                  {-1, 0, -4}, {1, 0, -4}, {0, 1, -4}, {0, 0, -5},  {9, 0, -5}, {0, 11, -5}};
  for (vec3 w : want)
    EXPECT_TRUE(std::any_of(corners.begin(), corners.end(), [&](vec3 c) { return glm::distance(c, w) < 1e-5f; }))
        << w.x << " " << w.y << " " << w.z;
  ASSERT_FALSE(m.normals.empty());
  int up = 0, down = 0;
  for (vec3 n : m.normals)
    up += glm::distance(n, vec3(0, 0, 1)) < 1e-6f, down += glm::distance(n, vec3(0, -1, 0)) < 1e-6f;
  EXPECT_GE(up, 1);
  EXPECT_GE(down, 1);
  // Integer types the extension does not allow are still errors.
  const uint32_t u32[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  GltfBuilder bad;
  bad.node({{"mesh", bad.mesh(bad.accessor(bad.view(u32, sizeof u32), 0, 5125, 3, "VEC3"))}});
  test::write_file(dir / "bad.gltf", bad.embedded());
  const std::string e = load_error(dir / "bad.gltf");
  EXPECT_NE(e.find("must be VEC3 of float"), std::string::npos) << e;
}

TEST(Gltf, StripsAndFansAreConvertedPointsAndLinesSkipped) {
  TempDir dir;
  std::vector<vec3> quad = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  GltfBuilder b;
  int strip = b.mesh(b.positions(quad), -1, -1, -1, 5);
  std::vector<vec3> fan = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  int fan_mesh = b.mesh(b.positions(fan), -1, -1, -1, 6);
  b.j["meshes"][size_t(fan_mesh)]["name"] = "fan\nny";  // a line break in a name is escaped in the warning
  b.j["meshes"][size_t(fan_mesh)]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", 1}});
  b.node({{"mesh", strip}});
  b.node({{"mesh", fan_mesh}, {"translation", {0, 0, 2}}});
  test::write_file(dir / "s.gltf", b.embedded());
  Scene s = load_ok(dir / "s.gltf");
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.indices.size(), 4u);
  for (uvec3 t : m.indices) {  // every triangle faces +z: the winding was kept
    vec3 n = glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
    EXPECT_GT(n.z, 0.0f);
  }
  EXPECT_TRUE(has_warning(s, "mesh 1 'fan\\nny': 1 primitive in mode 'lines' skipped")) << s.warnings.size();
}

/// Sparse substitutions of VEC3 accessor `acc` at `which` (unsigned byte indices), each moved to (0, 3, 0).
void sparse_positions(GltfBuilder& b, int acc, const std::vector<uint8_t>& which) {
  const std::vector<vec3> values(which.size(), vec3(0, 3, 0));
  const int iv = b.view(which.data(), which.size()), vv = b.view(values.data(), 12 * values.size());
  b.j["accessors"][size_t(acc)]["sparse"] = {{"count", which.size()},
                                             {"indices", {{"bufferView", iv}, {"componentType", 5121}}},
                                             {"values", {{"bufferView", vv}}}};
}

TEST(Gltf, SparseAccessorIsApplied) {
  TempDir dir;
  GltfBuilder b;
  int pos = b.positions(kTriangle);
  sparse_positions(b, pos, {2});
  b.node({{"mesh", b.mesh(pos)}});
  test::write_file(dir / "sp.gltf", b.embedded());
  Scene s = load_ok(dir / "sp.gltf");
  EXPECT_EQ(mesh_bounds(s).hi, vec3(1, 3, 0));
}

TEST(Gltf, NodeHierarchyWithTrsMatricesAndInstancing) {
  TempDir dir;
  GltfBuilder b;
  int mesh = b.mesh(b.positions(kTriangle));
  // Parent: translate (10,0,0) * rotate 90 degrees about z * scale (2,3,4): the scale is not uniform, so applying
  // it after the rotation instead of before would move the vertices. Child: a matrix translating by (0,5,0).
  double h = std::sqrt(0.5);
  int child = b.node({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}}, false);
  b.node({{"mesh", mesh}, {"translation", {10, 0, 0}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 3, 4}},
          {"children", {child}}});
  b.node({{"mesh", mesh}});  // the same mesh a third time, untransformed
  test::write_file(dir / "h.gltf", b.embedded());
  Scene s = load_ok(dir / "h.gltf");
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.indices.size(), 3u);
  glm::mat4 parent = glm::translate(glm::mat4(1), vec3(10, 0, 0)) *
                     glm::rotate(glm::mat4(1), glm::radians(90.0f), vec3(0, 0, 1)) *
                     glm::scale(glm::mat4(1), vec3(2, 3, 4));
  glm::mat4 child_world = parent * glm::translate(glm::mat4(1), vec3(0, 5, 0));
  glm::mat4 expected[3] = {parent, child_world, glm::mat4(1)};  // depth first: parent, child, second root
  for (int t = 0; t < 3; ++t)
    for (int k = 0; k < 3; ++k) {
      vec3 want(expected[t] * glm::vec4(kTriangle[size_t(k)], 1));
      EXPECT_LT(glm::distance(m.positions[m.indices[size_t(t)][k]], want), 1e-5f) << t << " " << k;
    }
}

TEST(Gltf, MirroringTransformKeepsTheFrontSide) {
  TempDir dir;
  GltfBuilder b;
  b.node({{"mesh", b.mesh(b.positions(kTriangle))}, {"scale", {-1, 1, 1}}});
  test::write_file(dir / "m.gltf", b.embedded());
  Scene s = load_ok(dir / "m.gltf");
  uvec3 t = s.meshes[0].indices[0];
  const auto& p = s.meshes[0].positions;
  EXPECT_GT(glm::cross(p[t.y] - p[t.x], p[t.z] - p[t.x]).z, 0.0f);  // still faces +z, as the unmirrored one
}

TEST(Gltf, FirstPerspectiveCameraWithItsNodeTransform) {
  TempDir dir;
  GltfBuilder b;
  b.node({{"mesh", b.mesh(b.positions(kTriangle))}});
  b.j["cameras"] = {{{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}},
                    {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}},
                    {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}}};
  b.node({{"camera", 0}});
  double h = std::sqrt(0.5);  // the second camera turned 90 degrees about y: it looks down -x
  b.node({{"camera", 1}, {"translation", {7, 0, 0}}, {"rotation", {0, h, 0, h}}});
  b.node({{"camera", 2}, {"translation", {0, 0, 5}}});
  test::write_file(dir / "c.gltf", b.embedded());
  Scene s = load_ok(dir / "c.gltf");
  ASSERT_EQ(s.cameras.size(), 2u);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_NEAR(s.camera->fov_deg, glm::degrees(0.5f), 1e-4f);
  EXPECT_LT(glm::distance(s.camera->eye, vec3(7, 0, 0)), 1e-5f);
  vec3 forward = glm::normalize(s.camera->target - s.camera->eye);
  EXPECT_LT(glm::distance(forward, vec3(-1, 0, 0)), 1e-5f);
  EXPECT_LT(glm::distance(glm::normalize(s.camera->up), vec3(0, 1, 0)), 1e-5f);
  EXPECT_LT(glm::distance(s.cameras[1].eye, vec3(0, 0, 5)), 1e-5f);
  EXPECT_TRUE(has_warning(s, "camera 0 skipped"));
  ASSERT_TRUE(select_camera(s, 1).empty());
  EXPECT_EQ(s.camera->eye, s.cameras[1].eye);
  EXPECT_NE(select_camera(s, 2).find("out of range"), std::string::npos);
}

TEST(Gltf, ACameraRollsWithItsNodeAndAimsAtTheScenesDepth) {
  // A camera at (0, 0, 10) rolled 90 degrees about its view axis (z): its up is the node's +y turned, -x. Its
  // target lies on its view axis at the depth of the scene's centre (the viewer orbits about it): the triangles
  // span z from -2 to 0, so 11 ahead of the eye.
  TempDir dir;
  GltfBuilder b;
  b.node({{"mesh", b.mesh(b.positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -2}, {1, 0, -2}, {0, 1, -2}}))}});
  b.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}};
  const double h = std::sqrt(0.5);
  b.node({{"camera", 0}, {"translation", {0, 0, 10}}, {"rotation", {0, 0, h, h}}});
  test::write_file(dir / "roll.gltf", b.embedded());
  Scene s = load_ok(dir / "roll.gltf");
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_LT(glm::distance(glm::normalize(s.camera->up), vec3(-1, 0, 0)), 1e-5f);
  EXPECT_LT(glm::distance(s.camera->eye, vec3(0, 0, 10)), 1e-5f);
  const vec3 centre = mesh_bounds(s).center();
  EXPECT_LT(glm::distance(s.camera->target, vec3(0, 0, centre.z)), 1e-4f);
}

TEST(Gltf, TheDefaultSceneAndAFileWithoutScenes) {
  TempDir dir;
  // Two scenes, "scene": 1: only scene 1's triangle (moved to x = 5) loads, with a warning naming it.
  GltfBuilder b;
  const int mesh = b.mesh(b.positions(kTriangle));
  b.node({{"mesh", mesh}});
  const int other = b.node({{"mesh", mesh}, {"translation", {5, 0, 0}}}, false);
  b.j["scenes"].push_back({{"nodes", {other}}});
  b.j["scene"] = 1;
  test::write_file(dir / "scenes.gltf", b.embedded());
  Scene s = load_ok(dir / "scenes.gltf");
  ASSERT_EQ(s.meshes[0].indices.size(), 1u);
  EXPECT_EQ(mesh_bounds(s).lo, vec3(5, 0, 0));
  EXPECT_TRUE(has_warning(s, "2 scenes: only scene 1 is loaded"));
  // No scenes at all: every node that is nobody's child is a root, and a child is placed once, under its parent.
  GltfBuilder n;
  const int child = n.node({{"mesh", n.mesh(n.positions(kTriangle))}, {"translation", {0, 3, 0}}}, false);
  n.node({{"children", {child}}, {"translation", {2, 0, 0}}}, false);
  n.j.erase("scenes");
  n.j.erase("scene");
  test::write_file(dir / "sceneless.gltf", n.embedded());
  Scene t = load_ok(dir / "sceneless.gltf");
  ASSERT_EQ(t.meshes[0].indices.size(), 1u);
  EXPECT_EQ(mesh_bounds(t).lo, vec3(2, 3, 0));
}

TEST(Gltf, NormalsFollowTheInverseTransposeOfAStretchingNode) {
  // A normal (1, 1, 0) / sqrt 2 under scale (2, 1, 1) stays perpendicular to the stretched surface: (1, 2, 0) /
  // sqrt 5, not the stretched vector (2, 1, 0) / sqrt 5.
  TempDir dir;
  GltfBuilder b;
  const std::vector<vec3> p = {{0, 0, 0}, {1, -1, 0}, {0, 0, 1}};
  const vec3 n0 = glm::normalize(vec3(1, 1, 0));
  const std::vector<vec3> nrm = {n0, n0, n0};
  b.node({{"mesh", b.mesh(b.positions(p), -1, -1, b.positions(nrm))}, {"scale", {2, 1, 1}}});
  test::write_file(dir / "n.gltf", b.embedded());
  Scene s = load_ok(dir / "n.gltf");
  const Mesh& m = s.meshes[0];
  ASSERT_EQ(m.normal_indices.size(), 1u);
  for (int k = 0; k < 3; ++k)
    EXPECT_LT(glm::distance(m.normals[m.normal_indices[0][k]], glm::normalize(vec3(1, 2, 0))), 1e-6f) << k;
}

TEST(Gltf, DegenerateTrianglesAreDroppedWithAWarning) {
  TempDir dir;
  GltfBuilder b;
  const std::vector<vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}};  // 2nd: a line
  b.node({{"mesh", b.mesh(b.positions(p))}});
  test::write_file(dir / "d.gltf", b.embedded());
  Scene s = load_ok(dir / "d.gltf");
  ASSERT_EQ(s.meshes[0].indices.size(), 1u);
  EXPECT_TRUE(has_warning(s, "1 degenerate (zero-area) triangle dropped"));
}

/// One triangle per material of `mats`, each on its own node, written to `path` and loaded back.
Scene load_material_triangles(GltfBuilder& b, const std::vector<json>& mats, const std::string& path) {
  for (size_t i = 0; i < mats.size(); ++i) {
    int mat = b.material(mats[i]);
    b.node({{"mesh", b.mesh(b.positions(kTriangle), -1, mat)}, {"translation", {0, 0, double(i)}}});
  }
  test::write_file(path, b.embedded());
  return load_ok(path);
}

const Material& material_named(const Scene& s, const std::string& name) {
  for (const Material& m : s.materials)
    if (m.name == name) return m;
  ADD_FAILURE() << "no material " << name;
  return s.materials.at(0);
}

TEST(Gltf, MaterialMapping) {
  TempDir dir;
  GltfBuilder b;
  auto pbr = [](std::vector<double> color, double metallic, double roughness) {
    return json{{"baseColorFactor", color}, {"metallicFactor", metallic}, {"roughnessFactor", roughness}};
  };
  std::vector<json> mats = {
      {{"name", "paint"}, {"pbrMetallicRoughness", pbr({0.5, 0.25, 0.125, 1}, 0, 0.5)}},
      {{"name", "chrome"}, {"pbrMetallicRoughness", pbr({0.9, 0.8, 0.7, 1}, 1, 0)}},
      {{"name", "brushed"}, {"pbrMetallicRoughness", pbr({0.9, 0.8, 0.7, 1}, 1, 0.2)}},
      {{"name", "rough-metal"}, {"pbrMetallicRoughness", pbr({0.9, 0.8, 0.7, 1}, 1, 0.6)}},
      {{"name", "water"}, {"pbrMetallicRoughness", pbr({1, 1, 1, 1}, 0, 0)},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}, {"KHR_materials_ior", {{"ior", 1.33}}}}}},
      {{"name", "glass"}, {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.9}}}}}},
      {{"name", "lamp"}, {"emissiveFactor", {1, 0.5, 0.25}}, {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
      {{"name", "leaf"}, {"alphaMode", "BLEND"}, {"pbrMetallicRoughness", pbr({0.1, 0.6, 0.1, 0.5}, 0, 1)}},
      // The thresholds themselves (README: ">= 0.5", "<= 0.3"), and an ior of 0 replaced.
      {{"name", "half-metal"}, {"pbrMetallicRoughness", pbr({0.9, 0.8, 0.7, 1}, 0.5, 0.3)}},
      {{"name", "half-clear"}, {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.5}}}}}},
      {{"name", "no-ior"},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}, {"KHR_materials_ior", {{"ior", 0}}}}}},
  };
  Scene s = load_material_triangles(b, mats, dir / "m.gltf");
  auto find = [&](const std::string& name) -> const Material& { return material_named(s, name); };
  EXPECT_EQ(find("paint").type, MaterialType::diffuse);
  EXPECT_EQ(find("paint").albedo, vec3(0.5f, 0.25f, 0.125f));
  EXPECT_EQ(find("chrome").type, MaterialType::specular);
  EXPECT_EQ(find("chrome").albedo, vec3(0.9f, 0.8f, 0.7f));
  EXPECT_EQ(find("brushed").type, MaterialType::specular);
  EXPECT_EQ(find("rough-metal").type, MaterialType::diffuse);
  EXPECT_EQ(find("water").type, MaterialType::glass);
  EXPECT_FLOAT_EQ(find("water").ior, 1.33f);
  EXPECT_EQ(find("glass").type, MaterialType::glass);
  EXPECT_FLOAT_EQ(find("glass").ior, 1.5f);
  EXPECT_EQ(find("lamp").emission, vec3(4.0f, 2.0f, 1.0f));
  EXPECT_TRUE(s.has_emitter());
  EXPECT_EQ(find("leaf").type, MaterialType::diffuse);
  EXPECT_EQ(find("half-metal").type, MaterialType::specular);
  EXPECT_TRUE(has_warning(s, "material 8 'half-metal' approximated: roughness 0.3 as a mirror"));
  EXPECT_EQ(find("half-clear").type, MaterialType::glass);
  EXPECT_EQ(find("no-ior").type, MaterialType::glass);
  EXPECT_FLOAT_EQ(find("no-ior").ior, 1.5f);
  EXPECT_TRUE(has_warning(s, "material 10 'no-ior' approximated: ior 0 replaced by 1.5"));
  // One warning per approximated material, naming it; none for the exact ones.
  EXPECT_TRUE(has_warning(s, "material 2 'brushed' approximated: roughness"));
  EXPECT_TRUE(has_warning(s, "material 3 'rough-metal' approximated: metal with roughness 0.6 as diffuse"));
  EXPECT_TRUE(has_warning(s, "material 5 'glass' approximated: transmission"));
  EXPECT_TRUE(has_warning(s, "material 7 'leaf' approximated: alphaMode BLEND ignored"));
  EXPECT_TRUE(has_warning(s, "material 2 'brushed' approximated: roughness 0.2 as a mirror"));
  EXPECT_FALSE(has_warning(s, "'paint'"));
  EXPECT_FALSE(has_warning(s, "'chrome'"));
  EXPECT_FALSE(has_warning(s, "'water'"));
  EXPECT_FALSE(has_warning(s, "'lamp'")) << testing::PrintToString(s.warnings);
}

/// A PNG of w x h RGBA pixels, encoded by stb_image_write.
std::string png(int w, int h, const std::vector<uint8_t>& rgba) {
  std::string out;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  EXPECT_NE(stbi_write_png_to_func(append, &out, w, h, 4, rgba.data(), 4 * w), 0);
  return out;
}

/// What IEC 61966-2-1 makes of an 8-bit sRGB value, written out here.
double linear(int v) {
  const double s = v / 255.0;
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

// A base-colour or emissive texture stands for its mean linear colour (README, glTF mapping): the mean of the
// decoded sRGB pixels, alpha ignored, times the factor. An image that cannot be decoded leaves the factor alone.
TEST(Gltf, TexturesBecomeTheirMeanLinearColourTimesTheFactor) {
  TempDir dir;
  GltfBuilder b;
  // Four pixels, one of them transparent (its colour still counts).
  const std::vector<uint8_t> rgba = {255, 0, 0, 255, 0, 0, 255, 0, 128, 64, 128, 128, 255, 255, 0, 255};
  const dvec3 mean((linear(255) + linear(128) + linear(255)) / 4, (linear(64) + linear(255)) / 4,
                   (linear(255) + linear(128)) / 4);
  b.j["images"] = {{{"uri", "data:image/png;base64," + test::base64(png(2, 2, rgba))}},
                   {{"uri", "data:image/png;base64," + test::base64("not a png at all")}}};
  b.j["textures"] = {{{"source", 0}}, {{"source", 1}}};
  std::vector<json> mats = {
      {{"name", "painted"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1, 0.25, 1}}, {"baseColorTexture", {{"index", 0}}}}}},
      {{"name", "screen"}, {"emissiveFactor", {2, 4, 8}}, {"emissiveTexture", {{"index", 0}}}},
      {{"name", "broken"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"baseColorTexture", {{"index", 1}}}}}},
  };
  Scene s = load_material_triangles(b, mats, dir / "t.gltf");
  auto find = [&](const std::string& name) -> const Material& { return material_named(s, name); };
  const vec3 painted = find("painted").albedo, screen = find("screen").emission;
  const dvec3 factor(0.5, 1, 0.25), emissive(2, 4, 8);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(painted[c], factor[c] * mean[c], 1e-5) << "channel " << c;
    EXPECT_NEAR(screen[c], emissive[c] * mean[c], 1e-5) << "channel " << c;
  }
  EXPECT_EQ(find("broken").albedo, vec3(0.5f));
  EXPECT_TRUE(has_warning(s, "'painted' approximated: base colour texture as its mean colour"));
  EXPECT_TRUE(has_warning(s, "'screen' approximated: emissive texture as its mean colour"));
  EXPECT_TRUE(has_warning(s, "'broken' approximated: base colour texture ignored (image 1: cannot decode"));
}

TEST(Gltf, GlbRoundTripEqualsGltf) {
  TempDir dir;
  GltfBuilder b;
  std::vector<vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}};
  std::vector<uint16_t> idx = {0, 1, 2, 2, 1, 3};
  int mat = b.material({{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.1, 0.1, 1}}}}});
  b.node({{"mesh", b.mesh(b.positions(p), b.indices(idx), mat)}, {"translation", {1, 2, 3}}});
  test::write_file(dir / "a.gltf", b.embedded());
  test::write_file(dir / "a.glb", b.glb());
  b.save_with_bin(dir / "c.gltf", dir.path.string(), "c.bin");
  Scene a = load_ok(dir / "a.gltf"), g = load_ok(dir / "a.glb"), c = load_ok(dir / "c.gltf");
  for (const Scene* s : {&g, &c}) {
    ASSERT_EQ(s->meshes.size(), 1u);
    EXPECT_EQ(s->meshes[0].positions, a.meshes[0].positions);
    EXPECT_EQ(s->meshes[0].indices, a.meshes[0].indices);
    EXPECT_EQ(s->materials[s->meshes[0].materials[0]].albedo, vec3(0.8f, 0.1f, 0.1f));
  }
  EXPECT_EQ(a.meshes[0].indices.size(), 2u);
}

TEST(Gltf, SceneJsonMeshShapeTransformsOverridesAndPicksCamera) {
  TempDir dir;
  GltfBuilder b;
  int mat = b.material({{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.1, 0.1, 1}}}}});
  b.node({{"mesh", b.mesh(b.positions(kTriangle), -1, mat)}});
  b.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}};
  b.node({{"camera", 0}, {"translation", {0, 0, 5}}});
  test::write_file(dir / "t.glb", b.glb());
  test::write_file(dir / "s.json", R"({"materials": {"blue": {"albedo": [0, 0, 1]}}, "shapes": [
    {"type": "mesh", "file": "t.glb", "transform": {"translate": [0, 0, -10]}, "camera": 0},
    {"type": "mesh", "file": "t.glb", "material": "blue", "transform": {"scale": 2}}]})");
  Scene s = load_ok(dir / "s.json");
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].world_position(s.meshes[0].indices[0].x), vec3(0, 0, -10));
  EXPECT_EQ(s.materials[s.meshes[0].materials[0]].name, "red");
  EXPECT_EQ(s.materials[s.meshes[1].materials[0]].name, "blue");
  EXPECT_EQ(mesh_bounds(s).hi, vec3(2, 2, 0));
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_LT(glm::distance(s.camera->eye, vec3(0, 0, -5)), 1e-5f);
  EXPECT_NEAR(s.camera->fov_deg, glm::degrees(0.7f), 1e-4f);

  test::write_file(dir / "bad.json", R"({"shapes": [{"type": "mesh", "file": "t.glb", "camera": 3}]})");
  EXPECT_NE(load_error(dir / "bad.json").find("camera 3 out of range"), std::string::npos);
  // The extension decides the format whatever its case.
  fs::copy_file(dir / "t.glb", dir / "T.GLB");
  test::write_file(dir / "upper.json", R"({"shapes": [{"type": "mesh", "file": "T.GLB"}]})");
  EXPECT_EQ(load_ok(dir / "upper.json").meshes.size(), 1u);
  // A rotating transform turns the camera's up with it (a quarter turn about z: +y up becomes -x).
  test::write_file(dir / "turned.json", R"({"shapes": [
    {"type": "mesh", "file": "t.glb", "transform": {"rotate": [0, 0, 1, 90]}, "camera": 0}]})");
  Scene turned = load_ok(dir / "turned.json");
  ASSERT_TRUE(turned.camera.has_value());
  EXPECT_LT(glm::distance(glm::normalize(turned.camera->up), vec3(-1, 0, 0)), 1e-5f);
  EXPECT_LT(glm::distance(turned.camera->eye, vec3(0, 0, 5)), 1e-5f);
  // The scene's own camera and a picked glTF camera conflict: which one was meant is not guessed.
  test::write_file(dir / "both.json", R"({"camera": {"eye": [0, 0, 3], "target": [0, 0, 0]}, "shapes": [
    {"type": "mesh", "file": "t.glb", "camera": 0}]})");
  EXPECT_NE(load_error(dir / "both.json").find("shapes[0].camera: the scene already has a \"camera\""),
            std::string::npos) << load_error(dir / "both.json");
}

// --- bad input ---------------------------------------------------------------------------------------------------

GltfBuilder triangle_file() {
  GltfBuilder b;
  b.node({{"mesh", b.mesh(b.positions(kTriangle))}});
  return b;
}

TEST(GltfBad, TruncatedGlbAndWrongMagic) {
  TempDir dir;
  std::string glb = triangle_file().glb();
  test::write_file(dir / "short.glb", glb.substr(0, 8));
  EXPECT_NE(load_error(dir / "short.glb").find("truncated .glb"), std::string::npos);
  test::write_file(dir / "cut.glb", glb.substr(0, glb.size() - 10));
  EXPECT_NE(load_error(dir / "cut.glb").find("truncated .glb"), std::string::npos);
  std::string magic = glb;
  magic[0] = 'x';
  test::write_file(dir / "magic.glb", magic);
  EXPECT_NE(load_error(dir / "magic.glb").find("wrong magic"), std::string::npos);
}

TEST(GltfBad, MissingBinAndBadDataUri) {
  TempDir dir;
  GltfBuilder b = triangle_file();
  test::write_file(dir / "nobin.gltf", b.with_buffer("missing.bin").dump());
  EXPECT_NE(load_error(dir / "nobin.gltf").find("missing.bin"), std::string::npos);
  test::write_file(dir / "uri.gltf", b.with_buffer("data:application/octet-stream;base64,@@@@").dump());
  std::string e = load_error(dir / "uri.gltf");
  EXPECT_NE(e.find("uri"), std::string::npos) << e;
}

TEST(GltfBad, RangesAndIndices) {
  TempDir dir;
  struct Case {
    const char* name;
    std::function<void(GltfBuilder&)> edit;
    const char* reason;
  };
  std::vector<Case> cases = {
      {"acc_range", [](GltfBuilder& b) { b.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7; },
       "POSITION accessor 7 out of range"},
      {"view_range", [](GltfBuilder& b) { b.j["accessors"][0]["bufferView"] = 5; }, "bufferView 5 out of range"},
      {"acc_overlap", [](GltfBuilder& b) { b.j["accessors"][0]["byteOffset"] = 4; }, "overlap the end of bufferView 0"},
      {"view_overlap", [](GltfBuilder& b) { b.j["bufferViews"][0]["byteOffset"] = 4; }, "overlap the end of buffer 0"},
      {"index", [](GltfBuilder& b) {
         std::vector<uint16_t> idx = {0, 1, 3};
         b.j["meshes"][0]["primitives"][0]["indices"] = b.indices(idx);
       }, "index 3 past the vertex count 3"},
      {"cycle", [](GltfBuilder& b) {
         b.j["nodes"].push_back({{"children", {2}}});
         b.j["nodes"].push_back({{"children", {1}}});
         b.j["scenes"][0]["nodes"].push_back(1);
       }, "cyclic node graph"},
      {"two_parents", [](GltfBuilder& b) { b.node({{"children", {0}}}); }, "more than one parent"},
      {"required", [](GltfBuilder& b) { b.j["extensionsRequired"] = {"KHR_draco_mesh_compression"}; },
       "unsupported required extension 'KHR_draco_mesh_compression'"},
      {"stride", [](GltfBuilder& b) { b.j["bufferViews"][0]["byteStride"] = 4; },
       "byteStride 4 is smaller than an element"},
      {"signed_indices", [](GltfBuilder& b) {
         std::vector<uint16_t> idx = {0, 1, 2};
         const int acc = b.indices(idx);
         b.j["accessors"][size_t(acc)]["componentType"] = 5122;  // signed short
         b.j["meshes"][0]["primitives"][0]["indices"] = acc;
       }, "must be SCALAR of unsigned byte, short or int"},
      {"sparse_index", [](GltfBuilder& b) { sparse_positions(b, 0, {0, 3}); }, "sparse index 3 past the count 3"},
      {"sparse_count", [](GltfBuilder& b) { sparse_positions(b, 0, {0, 1, 2, 0}); },
       "sparse count 4 exceeds the accessor's count"},
      {"normal_count",
       [](GltfBuilder& b) {
         b.j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = b.positions({{0, 0, 1}, {0, 0, 1}});
       },
       "NORMAL and POSITION counts differ"},
      {"material_range", [](GltfBuilder& b) { b.j["meshes"][0]["primitives"][0]["material"] = 3; },
       "material 3 out of range"},
      {"texture_range",
       [](GltfBuilder& b) {
         b.j["meshes"][0]["primitives"][0]["material"] =
             b.material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 5}}}}}});
       },
       "base colour texture 5 out of range"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    GltfBuilder b = triangle_file();
    c.edit(b);
    std::string path = dir / (std::string(c.name) + ".gltf");
    test::write_file(path, b.embedded());
    std::string e = load_error(path);
    EXPECT_NE(e.find(c.reason), std::string::npos) << e;
  }
}

TEST(GltfBad, NonFinitePositionAndMatrix) {
  TempDir dir;
  std::vector<vec3> p = kTriangle;
  p[1].x = std::numeric_limits<float>::infinity();
  GltfBuilder b;
  b.node({{"mesh", b.mesh(b.positions(p))}});
  test::write_file(dir / "p.gltf", b.embedded());
  EXPECT_NE(load_error(dir / "p.gltf").find("non-finite vertex position"), std::string::npos);
  // A finite matrix whose product overflows a float.
  GltfBuilder m = triangle_file();
  m.j["nodes"][0]["scale"] = {1e38, 1e38, 1e38};
  m.j["nodes"][0]["translation"] = {3e38, 0, 0};
  test::write_file(dir / "m.gltf", m.embedded());
  EXPECT_NE(load_error(dir / "m.gltf").find("non-finite"), std::string::npos);
}

}  // namespace
}  // namespace pt
