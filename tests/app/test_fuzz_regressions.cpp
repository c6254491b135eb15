// Every input the fuzzers ever crashed on (tests/data/bad/fuzz-<target>-*) stays fixed: it loads or gives exactly
// one error line; fuzz_render's inputs also build and render finite within their ray budget. The harness logic
// matches fuzz/fuzz_*.cpp (fuzz_render's is shared: fuzz/fuzz_render.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../../fuzz/fuzz_args.h"
#include "../../fuzz/fuzz_render.h"
#include "app/options.h"
#include "run_exe.h"
#include "render/renderer.h"
#include "scene/load.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }

/// What a successful load promises: every index in range, every coordinate finite, and the scene renders to a
/// finite image with no dropped samples.
void expect_valid_scene(Scene scene, const std::string& name) {
  const size_t nm = scene.materials.size();
  size_t triangles = 0;
  for (const Mesh& m : scene.meshes) {
    ASSERT_EQ(m.materials.size(), m.indices.size()) << name;
    for (const uvec3& t : m.indices)
      for (int c = 0; c < 3; ++c) ASSERT_LT(t[c], m.positions.size()) << name;
    for (uint32_t mat : m.materials) ASSERT_LT(mat, nm) << name;
    for (vec3 p : m.positions) ASSERT_TRUE(is_finite(p)) << name;
    if (!m.normal_indices.empty()) {
      ASSERT_EQ(m.normal_indices.size(), m.indices.size()) << name;
      for (const uvec3& t : m.normal_indices)
        for (int c = 0; c < 3; ++c) ASSERT_LT(t[c], m.normals.size()) << name;
    }
    triangles += m.indices.size();
  }
  for (const Quad& q : scene.quads) ASSERT_LT(q.material, nm) << name;
  for (const Sphere& sp : scene.spheres) ASSERT_LT(sp.material, nm) << name;
  EXPECT_GT(triangles + scene.quads.size() + scene.spheres.size(), 0u) << name << ": loaded, but empty";
  finalize_scene(scene);
  RenderScene rs = make_render_scene(scene);
  RenderParams p;
  p.width = p.height = 8;
  p.spp_per_frame = 2;
  Film film(p.width, p.height);
  RenderCounters c;
  Renderer(1).render_frame(rs, p, film, 0, c);
  EXPECT_EQ(c.samples, 128u) << name;
  EXPECT_EQ(c.nonfinite_samples, 0u) << name;
  for (size_t i = 0; i < film.count.size(); ++i) ASSERT_TRUE(is_finite(film.mean(i))) << name;
}

/// Runs one input through the harness of fuzz target `target` (fuzz_json, fuzz_obj, fuzz_gltf, fuzz_cli): it loads (and then
/// is a valid scene) or gives exactly one error line. Returns whether it loaded.
bool check_input(const std::string& target, const std::string& name, const std::string& text,
                 const test::TempDir& dir) {
  if (target == "fuzz_json") {
    Result<Scene> r = parse_json_scene(text, dir / "fuzz.json");
    if (!r.ok()) {
      EXPECT_TRUE(one_line(r.error())) << name << ": " << r.error();
      return false;
    }
    expect_valid_scene(std::move(*r), name);
    return true;
  }
  if (target == "fuzz_obj") {
    size_t split = text.find("\nnewmtl");
    std::ofstream(dir / "m.obj", std::ios::binary) << "mtllib m.mtl\n" << text.substr(0, split);
    std::ofstream(dir / "m.mtl", std::ios::binary) << (split == std::string::npos ? "" : text.substr(split));
    Result<Scene> r = load_scene(dir / "m.obj");
    if (!r.ok()) {
      EXPECT_TRUE(one_line(r.error())) << name << ": " << r.error();
      return false;
    }
    expect_valid_scene(std::move(*r), name);
    return true;
  }
  if (target == "fuzz_gltf") {
    std::string path = dir / (text.rfind("glTF", 0) == 0 ? "m.glb" : "m.gltf");
    std::ofstream(path, std::ios::binary) << text;
    std::ofstream(dir / "m.bin", std::ios::binary) << text;
    Result<Scene> r = load_scene(path);
    if (!r.ok()) {
      EXPECT_TRUE(one_line(r.error())) << name << ": " << r.error();
      return false;
    }
    expect_valid_scene(std::move(*r), name);
    return true;
  }
  if (target == "fuzz_render") {
    EXPECT_EQ(fuzz::check_render_input(text, dir.path), "") << name;
    return true;
  }
  if (target == "fuzz_cli") {
    std::vector<std::string> args = fuzz::split_args(text.data(), text.size());
    std::vector<const char*> argv;
    for (const std::string& a : args) argv.push_back(a.c_str());
    ParseOutcome out = parse_command_line(int(argv.size()), argv.data());
    EXPECT_TRUE(out.options || out.exit_code == 0 || out.exit_code == 2) << name;
    return out.options.has_value();
  }
  ADD_FAILURE() << name << ": no harness for fuzz target " << target;
  return false;
}

TEST(FuzzRegressions, EveryKeptCrashIsHandled) {
  test::TempDir dir;
  int n = 0;
  for (auto& e : fs::directory_iterator(fs::path(PTVIEW_TEST_DATA) / "bad")) {
    std::string name = e.path().filename().string();
    if (name.rfind("fuzz-", 0) != 0) continue;
    ++n;
    std::string target = name.substr(5, name.find('-', 5) - 5);  // fuzz-<target>-crash-<hash>
    check_input(target, name, test::read_file(e.path()), dir);
  }
  // The inputs are in the repository: finding none means the directory or the name pattern is wrong.
  ASSERT_GE(n, 2) << "no fuzz regression inputs found in " << PTVIEW_TEST_DATA << "/bad";
}

TEST(FuzzRegressions, SeedCorpusLoadsThroughTheSameHarness) {
  // The seeds the fuzzers start from mostly load, so the harness's "loaded" branch (expect_valid_scene) is
  // exercised even while every kept crash is an error.
  test::TempDir dir;
  int n = 0, loaded = 0;
  for (const char* kind : {"json", "obj", "cli"})
    for (auto& e : fs::directory_iterator(fs::path(PTVIEW_SOURCE_DIR) / "fuzz" / "corpus" / kind)) {
      ++n;
      loaded += check_input(std::string("fuzz_") + kind, e.path().string(), test::read_file(e.path()), dir);
    }
  ASSERT_GE(n, 10) << "seed corpus not found";
  EXPECT_GE(loaded, 8) << "of " << n;
}

}  // namespace
}  // namespace pt
