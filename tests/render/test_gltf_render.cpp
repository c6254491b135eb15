// The Cornell box of bench/data/cornell36.obj written as glTF (in code: its mesh moved to its own origin and placed
// back by a node translation, its MTL colours as baseColorFactor) renders the same image as the OBJ within noise.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "render/renderer.h"
#include "scene/gltf_fixture.h"
#include "scene/load.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

std::vector<double> render_mean(const Scene& scene, uint64_t seed) {
  RenderScene rs = make_render_scene(scene);
  RenderParams params;
  params.width = 48;
  params.height = 36;
  params.spp_per_frame = 8;
  params.seed = seed;
  Renderer renderer(2);
  Film film(params.width, params.height);
  RenderCounters c;
  for (int f = 0; f < 4; ++f) renderer.render_frame(rs, params, film, uint32_t(f), c);
  std::vector<double> mean(film.sum.size());
  for (size_t i = 0; i < mean.size(); ++i) mean[i] = double(film.sum[i]) / double(film.count[i / 3]);
  return mean;
}

double rms(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s / double(a.size()));
}

double average(const std::vector<double>& a) {
  double s = 0.0;
  for (double v : a) s += v;
  return s / double(a.size());
}

/// `scene`'s single mesh as a glTF file: one mesh, one primitive per material, placed by a node translation.
std::string as_gltf(const Scene& scene) {
  const Mesh& m = scene.meshes.at(0);
  vec3 center(0.0f);
  for (const vec3& p : m.positions) center += p / float(m.positions.size());
  std::vector<vec3> local;
  for (const vec3& p : m.positions) local.push_back(p - center);
  test::GltfBuilder b;
  int pos = b.positions(local);
  nlohmann::json mesh = {{"primitives", nlohmann::json::array()}};
  for (uint32_t mat = 0; mat < scene.materials.size(); ++mat) {
    std::vector<uint32_t> idx;
    for (size_t t = 0; t < m.indices.size(); ++t)
      if (m.materials[t] == mat)
        for (int k = 0; k < 3; ++k) idx.push_back(m.indices[t][k]);
    if (idx.empty()) continue;
    const Material& src = scene.materials[mat];
    vec3 a = src.albedo;
    int g = b.material({{"name", src.name},
                        {"pbrMetallicRoughness", {{"baseColorFactor", {a.x, a.y, a.z, 1.0}}, {"metallicFactor", 0.0},
                                                  {"roughnessFactor", 1.0}}}});
    mesh["primitives"].push_back({{"attributes", {{"POSITION", pos}}}, {"indices", b.indices(idx)}, {"material", g}});
  }
  b.j["meshes"].push_back(mesh);
  b.node({{"mesh", 0}, {"translation", {center.x, center.y, center.z}}});
  return b.embedded();
}

TEST(GltfRender, CornellBoxAsObjAndAsGltfRenderTheSameImage) {
  std::string obj_json = std::string(PTVIEW_SOURCE_DIR) + "/bench/data/cornell36.json";
  Result<Scene> obj = load_scene(obj_json);
  ASSERT_TRUE(obj.ok()) << obj.error();
  fs::path dir = fs::temp_directory_path() / ("ptview-gltf-cornell-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  test::write_file((dir / "cornell36.gltf").string(), as_gltf(*obj));
  // The same camera and background as bench/data/cornell36.json; only the mesh file differs.
  test::write_file((dir / "cornell36.json").string(),
                   R"({"camera": {"eye": [278, 273, -800], "target": [278, 273, 0], "up": [0, 1, 0], "fov": 37},
                       "background": [1, 1, 1], "shapes": [{"type": "mesh", "file": "cornell36.gltf"}]})");
  Result<Scene> gltf = load_scene((dir / "cornell36.json").string());
  fs::remove_all(dir);
  ASSERT_TRUE(gltf.ok()) << gltf.error();
  ASSERT_EQ(gltf->triangle_count(), obj->triangle_count());

  std::vector<double> obj0 = render_mean(*obj, 0), obj1 = render_mean(*obj, 1), gltf1 = render_mean(*gltf, 1);
  double noise = rms(obj0, obj1);  // two independent OBJ renders: the noise level alone
  double diff = rms(gltf1, obj0);  // glTF against OBJ with independent samples: noise, plus any bias
  ASSERT_GT(noise, 0.0);
  EXPECT_LT(diff, 1.2 * noise) << "noise " << noise << ", glTF vs OBJ " << diff;
  EXPECT_NEAR(average(gltf1), average(obj0), 0.02 * average(obj0));
}

}  // namespace
}  // namespace pt
