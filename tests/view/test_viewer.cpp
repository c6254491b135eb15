// The viewer tested as a person would use it: a real window under Xvfb, driven by scripted input through the same
// code paths as mouse and panels, checked through screenshots, saved images and the stats it writes at exit.
#include <gtest/gtest.h>
#include <unistd.h>
#include <stb_image.h>

#include <nlohmann/json.hpp>

#include "../app/run_exe.h"
#include "render/image.h"
#include "scene/builtin_assets.h"
#include "view/camera_control.h"
#include "view/display_mode.h"
#include "view/input.h"

namespace pt {
namespace {

namespace fs = std::filesystem;
using test::read_file;
using test::RunResult;
using test::shell_quote;
using test::TempDir;

bool have_xvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

/// Runs ptview in a window: under xvfb-run when available (CI), else on the current display. xvfb-run's -a alone
/// probes display numbers from 99 and races with any other xvfb-run starting at the same moment (another test
/// binary, a parallel CI job), so the probe starts at a number of our own.
/// `launcher` runs in front of ptview inside the display (mpirun for the offload test).
RunResult run_window(const std::vector<std::string>& args, const std::string& launcher = "") {
  std::string wrapper;
  if (have_xvfb()) wrapper = "xvfb-run -a -n " + std::to_string(100 + ::getpid() % 800) + " -s '-screen 0 1280x1024x24'";
  wrapper += " " + launcher;
  RunResult r = test::run_ptview(args, 240, wrapper);
  // xvfb-run itself sometimes fails to remove its temporary directory (exit 5) after the program ran, seen under
  // ASan on a loaded machine; that is the wrapper's failure, not ptview's: run once more.
  if (r.exit_code == 5 && r.err.find("xvfb-run: error: problem while cleaning up") != std::string::npos)
    r = test::run_ptview(args, 240, wrapper);
  return r;
}

#define REQUIRE_DISPLAY()                                                              \
  if (!have_xvfb() && !std::getenv("DISPLAY")) GTEST_SKIP() << "no xvfb-run and no DISPLAY"

struct Png {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;
  explicit Png(const std::string& path) {
    int n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 3);
    if (data) rgb.assign(data, data + size_t(w) * h * 3);
    stbi_image_free(data);
  }
  bool ok() const { return !rgb.empty(); }
  /// Mean and variance of luminance over the right part of the window (the image, right of the panels).
  std::pair<double, double> image_stats() const {
    double s = 0, s2 = 0;
    int n = 0;
    for (int y = 0; y < h; ++y)
      for (int x = w / 2; x < w; ++x) {
        const unsigned char* p = &rgb[(size_t(y) * w + x) * 3];
        double l = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        s += l;
        s2 += l * l;
        ++n;
      }
    return {s / n, s2 / n - (s / n) * (s / n)};
  }
};

/// The viewer's panel column is 360 pixels wide under Xvfb (scale 1): the image area is right of it.
constexpr int kPanelPx = 360;

std::string write_script(const TempDir& dir, const std::string& text) {
  std::string path = dir / "script.txt";
  std::ofstream(path) << text;
  return path;
}

/// The built-in scene's JSON with its camera replaced, written to `path`: the scene headless runs render.
void write_builtin_with_camera(const std::string& name, const Camera& c, const std::string& path) {
  for (const BuiltinAsset& a : builtin_assets())
    if (name == a.name) {
      nlohmann::json j = nlohmann::json::parse(a.json);
      j["camera"] = {{"eye", {c.eye.x, c.eye.y, c.eye.z}}, {"target", {c.target.x, c.target.y, c.target.z}},
                     {"up", {c.up.x, c.up.y, c.up.z}}, {"fov", c.fov_deg}};
      std::ofstream(path) << j.dump();
      return;
    }
  ADD_FAILURE() << "no built-in scene " << name;
}

Camera builtin_camera(const std::string& name) {
  for (const BuiltinAsset& a : builtin_assets())
    if (name == a.name) {
      nlohmann::json c = nlohmann::json::parse(a.json)["camera"];
      Camera cam;
      cam.eye = vec3(c["eye"][0].get<float>(), c["eye"][1].get<float>(), c["eye"][2].get<float>());
      cam.target = vec3(c["target"][0].get<float>(), c["target"][1].get<float>(), c["target"][2].get<float>());
      cam.up = vec3(c["up"][0].get<float>(), c["up"][1].get<float>(), c["up"][2].get<float>());
      cam.fov_deg = c["fov"].get<float>();
      return cam;
    }
  return {};
}

double mean_abs_diff(const Image& a, const Image& b) {
  if (a.rgb.size() != b.rgb.size() || a.rgb.empty()) return -1;
  double d = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) d += std::abs(double(a.rgb[i]) - double(b.rgb[i]));
  return d / double(a.rgb.size());
}

double mean(const Image& a) {
  double s = 0;
  for (float v : a.rgb) s += v;
  return a.rgb.empty() ? 0.0 : s / double(a.rgb.size());
}

TEST(Viewer, OpensAndShowsANonUniformImage) {
  REQUIRE_DISPLAY();
  TempDir dir;
  auto r = run_window({"--size", "256x256", "--quit-after-frames", "3", "--screenshot", dir / "shot.png",
                       "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png shot(dir / "shot.png");
  ASSERT_TRUE(shot.ok());
  auto [mean, var] = shot.image_stats();
  EXPECT_GT(mean, 10.0);
  EXPECT_GT(var, 100.0);  // walls, light and spheres, not a flat color
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  for (const char* key : {"spp", "seconds", "rays", "mrays_per_s", "nonfinite_samples", "bvh", "skipped",
                          "restart_latency_ms", "ui_fps"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_GE(j["spp"].get<int>(), 3);
  EXPECT_GE(j["restart_latency_ms"]["count"].get<int>(), 1);
  const double p50 = j["restart_latency_ms"]["p50"].get<double>(), p95 = j["restart_latency_ms"]["p95"].get<double>();
  EXPECT_GT(p50, 0.0);
  EXPECT_LE(p50, p95);
}

/// Mean absolute difference (of 255) between a window screenshot's image area and a saved render, which must fill
/// it 1:1 (Xvfb has scale 1: window units are framebuffer pixels); the render flipped as asked. -1 if the render
/// is not shown 1:1.
double shown_vs_saved(const Png& shot, const Png& render, bool flip_y = false, bool flip_x = false) {
  const ImageArea area = image_area(shot.w, shot.h, shot.w, float(kPanelPx), render.w, render.h);
  if (area.rect.w != render.w || area.rect.h != render.h) return -1;
  const int top = shot.h - area.rect.y - area.rect.h;  // the rectangle's first row, counted from the top
  double d = 0;
  for (int y = 0; y < render.h; ++y)
    for (int x = 0; x < render.w; ++x)
      for (int c = 0; c < 3; ++c) {
        const int ry = flip_y ? render.h - 1 - y : y, rx = flip_x ? render.w - 1 - x : x;
        d += std::abs(int(shot.rgb[(size_t(top + y) * shot.w + area.rect.x + x) * 3 + c]) -
                      int(render.rgb[(size_t(ry) * render.w + rx) * 3 + c]));
      }
  return d / (3.0 * render.w * render.h);
}

// The window shows the render itself: the screenshot's image area, at the place image_area gives, holds the image
// `save` writes (the same display transform), the right way up and not mirrored. A screenshot read bottom-up would
// still show a plausible picture.
TEST(Viewer, TheScreenshotShowsTheSavedImageTheRightWayUp) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(dir, "stop-at-spp 4\nwait-spp 4\nwait-frames 2\nsave " + dir / "render.png" +
                                             "\nscreenshot " + dir / "shot.png" + "\nquit\n");
  auto r = run_window({"--size", "200x120", "--script", script});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png shot(dir / "shot.png"), render(dir / "render.png");
  ASSERT_TRUE(shot.ok() && render.ok());
  ASSERT_EQ(render.w, 200);
  ASSERT_EQ(render.h, 120);
  // The render is 1:1 when the area is 200 wide.
  const double same = shown_vs_saved(shot, render), upside_down = shown_vs_saved(shot, render, true, false),
               mirrored = shown_vs_saved(shot, render, false, true);
  ASSERT_GE(same, 0.0) << "not shown 1:1 in a window of " << shot.w << " x " << shot.h;
  EXPECT_LT(same, 2.0) << "upside down " << upside_down << ", mirrored " << mirrored;
  EXPECT_GT(upside_down, same + 5.0);  // 14.5 against 0.0001 under Xvfb
  EXPECT_GT(mirrored, same + 5.0);
}

// Without --size the render follows the window's image area (the window less the 360-pixel panel column): `window`
// resizes the window and restarts at the new size, which the screen then shows 1:1. Also after a change of height
// alone (mutation DS3: the display texture must be re-created for it): at 40 x 100 a frame takes well under the
// 10 ms that needs a preview, so no reduced-size preview (of another width) comes between the two sizes. With
// --size the render keeps its size.
TEST(Viewer, TheRenderFollowsTheWindowUnlessItsSizeIsLocked) {
  REQUIRE_DISPLAY();
  TempDir dir;
  // Each epoch stops at 4 spp, so the image saved and the image shown are the same frame.
  auto saves = [&](const std::string& name) { return "wait-spp 4\nsave " + dir / name + "\n"; };
  auto shows = [&](const std::string& name) { return "screenshot " + dir / name + "\n"; };
  std::string script =
      write_script(dir, "stop-at-spp 4\nwait-frames 1\nwindow 600 500\nexpect-restart\n" + saves("a.png") +
                            "window 600 420\nexpect-restart\n" + saves("b.png") + shows("shot_b.png") +
                            "window 400 100\nwait-spp 4\nwindow 400 80\nexpect-restart\n" + saves("c.png") +
                            shows("shot_c.png") + "quit\n");
  auto r = run_window({"--threads", "2", "--script", script});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png a(dir / "a.png"), b(dir / "b.png"), c(dir / "c.png"), shot_b(dir / "shot_b.png"), shot_c(dir / "shot_c.png");
  ASSERT_TRUE(a.ok() && b.ok() && c.ok() && shot_b.ok() && shot_c.ok());
  EXPECT_EQ(a.w, 600 - kPanelPx);
  EXPECT_EQ(a.h, 500);
  EXPECT_EQ(b.w, 600 - kPanelPx);
  EXPECT_EQ(b.h, 420);
  EXPECT_EQ(c.w, 400 - kPanelPx);
  EXPECT_EQ(c.h, 80);
  for (const auto& [shot, saved] : {std::pair{&shot_b, &b}, std::pair{&shot_c, &c}}) {
    EXPECT_EQ(shot->w - kPanelPx, saved->w);
    EXPECT_EQ(shot->h, saved->h);
    const double shown = shown_vs_saved(*shot, *saved);
    EXPECT_GE(shown, 0.0) << saved->w << " x " << saved->h;
    EXPECT_LT(shown, 2.0) << saved->w << " x " << saved->h;
  }

  std::string locked = write_script(dir, "stop-at-spp 4\nwait-frames 1\nwindow 700 500\nexpect-no-restart\n" +
                                             saves("d.png") + shows("shot2.png") + "quit\n");
  r = run_window({"--size", "200x120", "--script", locked});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png d(dir / "d.png"), shot2(dir / "shot2.png");
  ASSERT_TRUE(d.ok() && shot2.ok());
  EXPECT_EQ(d.w, 200);
  EXPECT_EQ(d.h, 120);
  EXPECT_EQ(shot2.w, 700);
  EXPECT_EQ(shot2.h, 500);
}

// The orbit seen in the window is the orbit of camera_control.h: the viewer's image after `orbit 35 10` equals
// the headless render of the built-in scene with that camera, same size, seed and spp (bit for bit: both sum the
// same samples), and differs from the render of the camera before the orbit.
TEST(Viewer, OrbitShowsTheImageOfTheOrbitedCamera) {
  REQUIRE_DISPLAY();
  TempDir dir;
  // stop-at-spp before the orbit: the orbit's epoch then stops at exactly 4 samples (set after it, the epoch could
  // already be past 4 on a loaded machine).
  std::string script = write_script(dir, "stop-at-spp 4\nwait-frames 1\norbit 35 10\nexpect-restart\nwait-frames 4\n"
                                         "save " + dir / "viewer.pfm" + "\nquit\n");
  auto r = run_window({"--size", "96x64", "--max-depth", "6", "--script", script});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Camera before = builtin_camera("cornell-spheres"), after = before;
  orbit_camera(after, 35, 10);
  {
    // The orbit itself, independently of orbit_camera: the eye keeps its distance to the target, turns +35 degrees
    // about up (right-handed, so a mirrored orbit fails) and rises by 10 degrees of elevation.
    const dvec3 up = glm::normalize(dvec3(before.up)), o0 = dvec3(before.eye - before.target),
                o1 = dvec3(after.eye - after.target);
    EXPECT_NEAR(glm::length(o1), glm::length(o0), 1e-4 * glm::length(o0));
    auto flat = [&](dvec3 v) { return glm::normalize(v - glm::dot(v, up) * up); };
    const double yaw = std::atan2(glm::dot(glm::cross(flat(o0), flat(o1)), up), glm::dot(flat(o0), flat(o1)));
    EXPECT_NEAR(glm::degrees(yaw), 35.0, 1e-3);
    auto elevation = [&](dvec3 v) { return glm::degrees(std::asin(glm::dot(glm::normalize(v), up))); };
    EXPECT_NEAR(elevation(o1) - elevation(o0), 10.0, 1e-3);
  }
  write_builtin_with_camera("cornell-spheres", after, dir / "after.json");
  write_builtin_with_camera("cornell-spheres", before, dir / "before.json");
  for (const char* name : {"after", "before"}) {
    auto h = test::run_ptview({dir / (std::string(name) + ".json"), "--frames", "4", "--size", "96x64", "--max-depth",
                               "6", "--out", dir / (std::string(name) + ".pfm")});
    ASSERT_EQ(h.exit_code, 0) << h.err;
  }
  Result<Image> viewer = load_image(dir / "viewer.pfm"), expected = load_image(dir / "after.pfm"),
                unorbited = load_image(dir / "before.pfm");
  ASSERT_TRUE(viewer.ok() && expected.ok() && unorbited.ok());
  EXPECT_EQ(viewer->rgb, expected->rgb) << "mean |viewer - expected| " << mean_abs_diff(*viewer, *expected);
  EXPECT_GT(mean_abs_diff(*viewer, *unorbited), 0.01);
}

// pan, dolly, light-intensity and wait-ms, each with an effect that can be checked.
TEST(Viewer, PanDollyLightIntensityAndWaitMs) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(
      // Every saved image comes from an epoch that began after stop-at-spp 2, so each holds exactly 2 samples per
      // pixel: the first epoch may already be past 2 when the script starts (it did on a loaded machine).
      dir, "stop-at-spp 2\nlight-intensity 0.5\nexpect-restart\nwait-frames 2\nsave " + dir / "a.pfm" +
               "\nlight-intensity 4\nexpect-restart\nwait-frames 2\nsave " + dir / "b.pfm" +
               "\npan 0.1 0\nexpect-restart\ndolly 0.7\nexpect-restart\nwait-frames 2\nsave " + dir / "c.pfm" +
               "\nquit\n");
  auto r = run_window({"--size", "64x64", "--max-depth", "4", "--script", script, "--stats-json", dir / "s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  {
    // Restarts at the start, after the light edit and after pan + dolly (edits before the next frame share one
    // latency), each timed: the latency summary counts them and is ordered.
    auto j = nlohmann::json::parse(read_file(dir / "s.json"));
    const auto& lat = j["restart_latency_ms"];
    EXPECT_GE(lat["count"].get<int>(), 3);
    EXPECT_GT(lat["p50"].get<double>(), 0.0);
    EXPECT_LE(lat["p50"].get<double>(), lat["p95"].get<double>());
  }
  {
    // wait-ms alone: the run lasts at least the wait (a wait of half the time fails: start-up is far below 2 s).
    std::string wait = write_script(dir, "wait-ms 4000\nquit\n");
    auto t0 = std::chrono::steady_clock::now();
    auto w = run_window({"--size", "16x16", "--script", wait});
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(w.exit_code, 0) << w.err;
    EXPECT_GE(seconds, 4.0) << "wait-ms 4000 waited less";
  }
  Result<Image> a = load_image(dir / "a.pfm"), b = load_image(dir / "b.pfm"), c = load_image(dir / "c.pfm");
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  // The same samples with four times the emission (half, then twice the original): radiance is linear in it.
  EXPECT_NEAR(mean(*b) / mean(*a), 4.0, 4e-3);
  Camera cam = builtin_camera("cornell-spheres");
  pan_camera(cam, 0.1f, 0.0f);
  dolly_camera(cam, 0.7f, 0.0f);  // far above the floor: the viewer's floor does not matter here
  write_builtin_with_camera("cornell-spheres", cam, dir / "moved.json");
  auto h = test::run_ptview({dir / "moved.json", "--frames", "2", "--size", "64x64", "--max-depth", "4", "--out",
                             dir / "moved.pfm"});
  ASSERT_EQ(h.exit_code, 0) << h.err;
  Result<Image> moved = load_image(dir / "moved.pfm");
  ASSERT_TRUE(moved.ok());
  // Headless with the original emission: half the viewer's brightness, pixel for pixel.
  for (float& v : moved->rgb) v *= 2.0f;
  EXPECT_LT(mean_abs_diff(*c, *moved), 1e-3 * mean(*c));
}

TEST(Viewer, MaterialEditRestartsAndChangesThePickedObject) {
  REQUIRE_DISPLAY();
  TempDir dir;
  // Pixel (64, 200) of 256x256 lies on the mirror sphere of the default scene; make it blue diffuse.
  std::string script = write_script(dir, "wait-frames 4\nsave " + dir / "before.pfm" +
                                             "\npick 64 200\nset-material diffuse albedo=0.05,0.05,0.9\n"
                                             "expect-restart\nwait-frames 4\nsave " + dir / "after.pfm" + "\nquit\n");
  auto r = run_window({"--size", "256x256", "--script", script, "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Result<Image> before = load_image(dir / "before.pfm"), after = load_image(dir / "after.pfm");
  ASSERT_TRUE(before.ok() && after.ok());
  // Around the picked point the object now reflects mostly blue.
  double rb = 0, bb = 0, ra = 0, ba = 0;
  for (int y = 190; y < 210; ++y)
    for (int x = 54; x < 74; ++x) {
      rb += before->at(x, y).x;
      bb += before->at(x, y).z;
      ra += after->at(x, y).x;
      ba += after->at(x, y).z;
    }
  EXPECT_GT(ba / (ra + 1e-6), 2.0 * bb / (rb + 1e-6)) << "before r/b " << rb << "/" << bb << " after " << ra << "/" << ba;
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_GE(j["epoch"].get<int>(), 2);  // restarted: the spp count started over in a new epoch
  EXPECT_GE(j["spp"].get<int>(), 4);    // ... and grew again
}

TEST(Viewer, ExposureDoesNotRestartButOrbitDoes) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string ok = write_script(dir, "wait-frames 2\nexposure 2\nexpect-no-restart\ntonemap aces\nexpect-no-restart\n"
                                     "light-size 1.0 0.6\nexpect-restart\nwait-frames 2\nquit\n");
  auto r = run_window({"--size", "128x128", "--script", ok});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // The check itself can fail: an orbit is a restart.
  std::string bad = write_script(dir, "wait-frames 1\norbit 10 0\nexpect-no-restart\nquit\n");
  r = run_window({"--size", "128x128", "--script", bad});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("script.txt:3:"), std::string::npos) << r.err;
}

TEST(Viewer, LoadingAMeshRebuildsTheBvh) {
  REQUIRE_DISPLAY();
  TempDir dir;
  // PTVIEW_TEST_NO_SHARED=1 takes the path of a clone without ../shared.
  fs::path bunny = fs::path(PTVIEW_SOURCE_DIR) / ".." / "shared" / "models" / "stanford-bunny.obj";
  if (std::getenv("PTVIEW_TEST_NO_SHARED")) bunny = fs::path(dir / "absent.obj");
  std::string mesh = bunny.string();
  size_t expected = 69451 + 2;  // plus the default light
  if (!fs::exists(bunny)) {
    // A small generated mesh instead: a 20x20 grid of quads.
    mesh = dir / "grid.obj";
    std::ofstream f(mesh);
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j) f << "v " << i * 0.1 << " " << 0.05 * std::sin(i + j) << " " << j * 0.1 << "\n";
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j) {
        int a = i * 21 + j + 1;
        f << "f " << a << " " << a + 1 << " " << a + 22 << " " << a + 21 << "\n";
      }
    expected = 800 + 2;
  }
  std::string script = write_script(dir, "wait-frames 1\nload " + mesh + "\nwait-frames 2\nscreenshot " +
                                             dir / "loaded.png" + "\nquit\n");
  auto r = run_window({"--size", "256x256", "--script", script, "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  // The new scene is the one rendered, over a BVH built for it (the built-in scene has 32 triangles and 2
  // spheres): its primitives are the mesh's triangles, and it took a second build.
  EXPECT_EQ(j["triangles"].get<size_t>(), expected);
  EXPECT_EQ(j["bvh"]["primitives"].get<size_t>(), expected);
  EXPECT_EQ(j["geometry_builds"].get<int>(), 2);
  EXPECT_GE(j["bvh"]["nodes"].get<size_t>(), expected / 64) << "8 children per node, at most 8 triangles per leaf";
  auto [mean, var] = Png(dir / "loaded.png").image_stats();
  EXPECT_GT(var, 10.0);
}

/// The public Cornell box OBJ (bench/data/cornell36.obj) with an emissive light: its light is two triangles.
std::string cornell36_with_light(const TempDir& dir) {
  fs::copy_file(fs::path(PTVIEW_SOURCE_DIR) / "bench/data/cornell36.obj", dir / "cornell36.obj");
  // The box is open toward -z: the camera of bench/data/cornell36.json, without its background.
  std::ofstream(dir / "cornell36.json")
      << R"({"camera": {"eye": [278, 273, -800], "target": [278, 273, 0], "fov": 37},
            "shapes": [{"type": "mesh", "file": "cornell36.obj"}]})";
  std::ofstream(dir / "cornell36.mtl") << "newmtl white\nKd 0.73 0.73 0.73\nnewmtl red\nKd 0.65 0.05 0.05\n"
                                          "newmtl green\nKd 0.12 0.45 0.15\nnewmtl light\nKd 0.78 0.78 0.78\n"
                                          "Ke 17 12 4\n";
  return dir / "cornell36.json";
}

// Every light of the built-in scenes and of a two-triangle-light OBJ can be selected and resized by script; the
// screenshots are looked at by hand (see the report), the run checks that every step restarted and succeeded.
TEST(Viewer, EveryLightCanBeSelectedAndResized) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string obj = cornell36_with_light(dir);
  std::string text = "stop-at-spp 2\n";
  // (scene, light count): cornell-spheres has one rectangle light; the OBJ one triangle pair.
  for (auto [scene, lights] : {std::pair<std::string, int>{"builtin:cornell", 1}, {"builtin:cornell-glass", 1},
                               {"builtin:cornell-mirror", 1}, {"builtin:cornell-spheres", 1}, {obj, 1}}) {
    text += "load " + scene + "\nwait-frames 2\n";
    const std::string size = scene == obj ? "300 100" : "0.3 0.6";  // the OBJ is in millimetres
    for (int l = 0; l < lights; ++l)
      text += "light " + std::to_string(l) + "\nlight-scale 1.6\nexpect-restart\nlight-size " + size +
              "\nexpect-restart\n";
    std::string name = fs::path(scene).stem().string();
    if (name.rfind("builtin:", 0) == 0) name = name.substr(8);
    text += "wait-frames 2\nscreenshot " + dir / ("lights-" + name + ".png") + "\n";
  }
  text += "light 1\nquit\n";
  std::string script = write_script(dir, text);
  auto r = run_window({"--size", "128x128", "--script", script, "--stats-json", dir / "stats.json"});
  EXPECT_EQ(r.exit_code, 3) << r.err;  // only the last "light 1" fails: the OBJ has one light
  EXPECT_NE(r.err.find("light: the scene has 1 light(s)"), std::string::npos) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(j["geometry_builds"].get<int>(), 6) << "one build per load, none per light edit";
  EXPECT_EQ(j["geometry_refits"].get<int>(), 10);
  if (const char* keep = std::getenv("PTVIEW_KEEP_SCREENSHOTS"))
    for (const auto& e : fs::directory_iterator(dir.path))
      if (e.path().extension() == ".png") fs::copy_file(e.path(), fs::path(keep) / e.path().filename(),
                                                        fs::copy_options::overwrite_existing);
}

// A scene edited in the viewer and saved renders the same headless: bit for bit, since both sum the same samples
// of the same triangles in the same order. Once with an edited two-triangle light (the mesh is written next to
// the JSON), once with only a camera edit (the JSON names the original OBJ).
TEST(Viewer, ASavedSceneRendersHeadlessAsTheViewerShowsIt) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string obj = cornell36_with_light(dir);
  fs::create_directories(dir / "out");
  for (bool edit_light : {true, false}) {
    std::string edits = edit_light ? "light 0\nlight-size 250 80\nlight-intensity 0.5\npick 40 25\n"
                                     "set-material specular albedo=0.9,0.9,0.5\n"
                                   : "";
    std::string script = write_script(dir, "stop-at-spp 3\nwait-frames 1\norbit 12 -4\n" + edits +
                                               "wait-frames 3\nsave " + dir / "out/viewer.pfm" + "\nsave-scene " +
                                               dir / "out/saved.json" + "\nquit\n");
    auto r = run_window({obj, "--size", "80x60", "--max-depth", "5", "--script", script});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto j = nlohmann::json::parse(read_file(dir / "out/saved.json"));
    std::string file = j["shapes"][0]["file"].get<std::string>();
    if (edit_light) {
      EXPECT_EQ(file, "saved.mesh0.obj");
    } else {
      EXPECT_EQ(file, "../cornell36.obj") << "an unedited mesh is named by its file, relative to the JSON";
    }
    auto h = test::run_ptview({dir / "out/saved.json", "--frames", "3", "--size", "80x60", "--max-depth", "5",
                               "--out", dir / "out/headless.pfm"});
    ASSERT_EQ(h.exit_code, 0) << h.err;
    Result<Image> viewer = load_image(dir / "out/viewer.pfm"), headless = load_image(dir / "out/headless.pfm");
    ASSERT_TRUE(viewer.ok() && headless.ok());
    EXPECT_GT(mean(*viewer), 0.01) << "not black";
    EXPECT_EQ(viewer->rgb, headless->rgb) << "edit_light " << edit_light << ": mean |difference| "
                                          << mean_abs_diff(*viewer, *headless);
  }
}

/// Mean absolute difference of two screenshots over the image area.
double image_area_diff(const Png& a, const Png& b) {
  if (a.w != b.w || a.h != b.h || !a.ok()) return -1;
  double d = 0;
  size_t n = 0;
  for (int y = 0; y < a.h; ++y)
    for (int x = kPanelPx; x < a.w; ++x, ++n)
      for (int c = 0; c < 3; ++c) d += std::abs(int(a.rgb[(size_t(y) * a.w + x) * 3 + c]) - int(b.rgb[(size_t(y) * a.w + x) * 3 + c]));
  return d / double(n * 3);
}

/// Close to the heat colour map's top colour (252, 255, 163) in sRGB.
bool is_top_heat(const unsigned char* q) {
  return std::abs(q[0] - 252) < 8 && std::abs(q[1] - 255) < 8 && std::abs(q[2] - 163) < 10;
}

/// The count of a screenshot's pixels in columns [x0, x1), rows [y0, y1) that `pred` accepts.
template <class Pred>
size_t region_count(const Png& p, int x0, int x1, int y0, int y1, Pred pred) {
  size_t n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += pred(&p.rgb[(size_t(y) * p.w + x) * 3]);
  return n;
}

/// Count of image-area pixels of the heat colour map's top colour.
size_t top_heat_pixels(const Png& p) { return region_count(p, kPanelPx, p.w, 0, p.h, is_top_heat); }

TEST(Viewer, DisplayModesChangeThePixelsWithoutRestarting) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(
      dir, "stop-at-spp 24\nwait-frames 6\nscreenshot " + dir / "image.png" +
               "\ndisplay error\nexpect-no-restart\nscreenshot " + dir / "error.png" +
               "\ndisplay samples\nexpect-no-restart\nscreenshot " + dir / "samples.png" +
               "\ndisplay image\nexpect-no-restart\nscreenshot " + dir / "image2.png" + "\nquit\n");
  auto r = run_window({"--size", "96x64", "--max-depth", "4", "--script", script, "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png image(dir / "image.png"), error(dir / "error.png"), samples(dir / "samples.png"), image2(dir / "image2.png");
  ASSERT_TRUE(image.ok() && error.ok() && samples.ok() && image2.ok());
  // The 96 x 64 render is about an eighth of the image area (the rest is letterbox margin and the legend).
  EXPECT_GT(image_area_diff(image, error), 2.0) << "the error heatmap must differ from the image";
  EXPECT_GT(image_area_diff(error, samples), 2.0);
  // Without adaptive sampling every pixel has the most samples: the samples map is the top colour throughout.
  EXPECT_GT(top_heat_pixels(samples), size_t(96 * 64 * 9 / 10));
  EXPECT_LT(top_heat_pixels(image), size_t(96 * 64 / 20));
  EXPECT_LT(image_area_diff(image, image2), image_area_diff(image, error)) << "back to the image";
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(j["epoch"].get<int>(), 1) << "no display mode restarted";
  EXPECT_EQ(j["display_mode"], "image");
  EXPECT_GT(j["est_rel_mse"].get<double>(), 0.0) << "the session frame's estimate reaches the stats JSON";
}

TEST(Viewer, ReferenceErrorModeAndTrueRelMse) {
  REQUIRE_DISPLAY();
  TempDir dir;
  auto h = test::run_ptview({"--size", "64x48", "--max-depth", "4", "--frames", "64", "--out", dir / "ref.pfm"}, 120);
  ASSERT_EQ(h.exit_code, 0) << h.err;
  // The render keeps the reference's size: the window's image area (far larger) is not followed, however long
  // the viewer waits (the follower's debounce is 0.25 s).
  std::string script = write_script(dir, "wait-frames 2\nscreenshot " + dir / "image.png" +
                                             "\ndisplay reference-error\nexpect-no-restart\nscreenshot " +
                                             dir / "referr.png" + "\nwait-ms 800\nexpect-no-restart\nquit\n");
  auto r = run_window({"--max-depth", "4", "--reference", dir / "ref.pfm", "--script", script, "--stats-json",
                       dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png image(dir / "image.png"), referr(dir / "referr.png");
  EXPECT_GT(image_area_diff(image, referr), 1.0);
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(j["width"], 64) << "the render takes the reference's size";
  EXPECT_EQ(j["display_mode"], "reference-error");
  ASSERT_TRUE(j["rel_mse"].is_number()) << j.dump();
  EXPECT_GT(j["rel_mse"].get<double>(), 0.0);
  // Without a reference the mode is refused: a failed script command (exit 3, FILE:LINE).
  std::string bad = write_script(dir, "wait-frames 1\ndisplay reference-error\nquit\n");
  auto b = run_window({"--size", "64x48", "--script", bad});
  EXPECT_EQ(b.exit_code, 3);
  EXPECT_NE(b.err.find("script.txt:2: display reference-error: needs --reference"), std::string::npos) << b.err;
  // A size given with --size must be the reference's (the error image compares pixel for pixel).
  auto sized = run_window({"--size", "32x24", "--reference", dir / "ref.pfm", "--script", bad});
  EXPECT_EQ(sized.exit_code, 2);
  EXPECT_NE(sized.err.find("reference is 64x48, the render 32x24"), std::string::npos) << sized.err;
}

/// Mean luminance and its variance over columns [x0, x1) of a screenshot's rows [y0, y1).
std::pair<double, double> region_stats(const Png& p, int x0, int x1, int y0, int y1) {
  double s = 0, s2 = 0;
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x, ++n) {
      const unsigned char* q = &p.rgb[(size_t(y) * p.w + x) * 3];
      double l = 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
      s += l;
      s2 += l * l;
    }
  return {s / n, s2 / n - (s / n) * (s / n)};
}

TEST(Viewer, EqualTimeCompareShowsBothSidesAndTheirStats) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(
      dir, "wait-frames 1\ncompare integrator=nee sampler=independent\nexpect-restart\nwait-frames 4\n"
           "divider 0.5\nexpect-no-restart\nwait-ms 200\nscreenshot " + dir / "ab.png" +
           "\ncompare integrator=bsdf\nexpect-restart\nwait-frames 2\nquit\n");
  auto r = run_window({"--size", "128x96", "--max-depth", "4", "--script", script, "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png ab(dir / "ab.png");
  ASSERT_TRUE(ab.ok());
  // The 128 x 96 render is letterboxed centred in the image area right of the 360-pixel panel column: both halves
  // of it (clear of the divider line) must show the scene (lit, with structure).
  const int area_w = ab.w - kPanelPx, x0 = kPanelPx + (area_w - 128) / 2, y0 = (ab.h - 96) / 2;
  auto left = region_stats(ab, x0 + 4, x0 + 56, y0 + 4, y0 + 92);
  auto right = region_stats(ab, x0 + 72, x0 + 124, y0 + 4, y0 + 92);
  EXPECT_GT(left.first, 15.0);
  EXPECT_GT(right.first, 15.0);
  EXPECT_GT(left.second, 20.0);
  EXPECT_GT(right.second, 20.0);
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  ASSERT_TRUE(j.contains("compare")) << j.dump();
  for (const char* side : {"a", "b"}) {
    EXPECT_GT(j["compare"][side]["spp"].get<int>(), 0) << side;
    EXPECT_GT(j["compare"][side]["seconds"].get<double>(), 0.0) << side;
    EXPECT_TRUE(j["compare"][side].contains("rel_mse")) << side;
  }
  EXPECT_EQ(j["compare"]["b"]["integrator"], "bsdf");
  std::string bad = write_script(dir, "compare integrator=path\n");
  auto b = run_window({"--size", "64x48", "--script", bad});
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("script.txt:1:"), std::string::npos) << b.err;
}

/// The fraction of the pixels in columns [x0, x1), rows [y0, y1) that `pred` accepts (region_count).
template <class Pred>
double region_fraction(const Png& p, int x0, int x1, int y0, int y1, Pred pred) {
  const size_t n = size_t(std::max(0, x1 - x0)) * size_t(std::max(0, y1 - y0));
  return n ? double(region_count(p, x0, x1, y0, y1, pred)) / double(n) : 0.0;
}

/// Within a few levels of some colour of the heat map (display_mode.h heat_srgb): a heatmap pixel, not an image's.
bool on_heat_ramp(const unsigned char* q) {
  static const std::vector<vec3> ramp = [] {
    std::vector<vec3> r;
    for (int i = 0; i <= 512; ++i) r.push_back(heat_srgb(float(i) / 512.0f) * 255.0f);
    return r;
  }();
  for (const vec3& c : ramp)
    if (std::abs(q[0] - c.x) < 6 && std::abs(q[1] - c.y) < 6 && std::abs(q[2] - c.z) < 6) return true;
  return false;
}

// Each side of a compare is drawn from its own session, on its own side of the divider, and both are redrawn when
// the display mode changes, even once both have stopped and no new frame will come. B samples adaptively and A does
// not, so their sample maps differ: A's is the top colour throughout, B's mostly not. A heatmap ignores the
// exposure (it is display-ready), with or without a compare.
TEST(Viewer, ACompareDrawsEachSideOnItsOwnHalfAndRedrawsBothOnADisplayChange) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(
      dir, "stop-at-spp 32\nexposure 3\ncompare adaptive=0.5\nexpect-restart\ndivider 0.5\nwait-frames 32\n"
           "wait-ms 300\ndisplay samples\nexpect-no-restart\nscreenshot " + dir / "ab.png" +
           "\ndisplay image\nscreenshot " + dir / "ab_image.png" + "\ndisplay samples\ncompare off\n"
           "expect-no-restart\nscreenshot " + dir / "a.png" + "\nquit\n");
  auto r = run_window({"--size", "128x96", "--max-depth", "4", "--script", script, "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Png ab(dir / "ab.png"), ab_image(dir / "ab_image.png"), a(dir / "a.png");
  ASSERT_TRUE(ab.ok() && ab_image.ok() && a.ok());
  // As in EqualTimeCompareShowsBothSidesAndTheirStats: the render's place in the window; rows below the A and B
  // labels, columns clear of the divider.
  const int area_w = ab.w - kPanelPx, x0 = kPanelPx + (area_w - 128) / 2, y0 = (ab.h - 96) / 2;
  const double left_top = region_fraction(ab, x0 + 2, x0 + 58, y0 + 20, y0 + 94, is_top_heat),
               right_top = region_fraction(ab, x0 + 70, x0 + 126, y0 + 20, y0 + 94, is_top_heat),
               right_heat = region_fraction(ab, x0 + 70, x0 + 126, y0 + 20, y0 + 94, on_heat_ramp);
  EXPECT_GT(left_top, 0.95) << "A, without adaptive sampling: every pixel has the most samples";
  EXPECT_GT(right_heat, 0.95) << "B's side shows its sample map, not its image";
  EXPECT_LT(right_top, 0.6) << "B's adaptive sampling stopped many pixels early";
  EXPECT_LT(region_fraction(ab_image, x0 + 70, x0 + 126, y0 + 20, y0 + 94, on_heat_ramp), 0.5)
      << "back to the image on B's side too";
  EXPECT_GT(region_fraction(a, x0 + 2, x0 + 126, y0 + 2, y0 + 94, is_top_heat), 0.95) << "A alone, exposure ignored";
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(j["spp"].get<int>(), 32);
  EXPECT_EQ(j["display_mode"], "samples");
}

TEST(Viewer, AdaptiveThresholdChangesNeverRestart) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(dir,
                                    "wait-frames 2\nnoise-threshold 0.5 4\nexpect-no-restart\nwait-ms 300\n"
                                    "noise-threshold 0.05\nexpect-no-restart\ndisplay samples\nwait-ms 300\nquit\n");
  auto r = run_window({"--size", "64x48", "--max-depth", "4", "--script", script, "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(j["epoch"].get<int>(), 1);
  EXPECT_EQ(j["noise_threshold"].get<double>(), 0.05);
  std::string bad = write_script(dir, "noise-threshold 1.5\n");
  auto b = run_window({"--size", "64x48", "--script", bad});
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("script.txt:1:"), std::string::npos) << b.err;
}

#ifdef PTVIEW_MPIEXEC
/// mpirun with K ranks, as tests/app/test_mpi.cpp runs it (as root, in a container).
std::string mpirun(int ranks) {
  return "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none "
         "ASAN_OPTIONS=detect_leaks=0 " + shell_quote(PTVIEW_MPIEXEC) + " -q --oversubscribe --bind-to none -np " +
         std::to_string(ranks);
}
#endif

// The viewer offload (view/offload.h) with 3 ranks: an orbit, a light resize (BVH refit) and a light intensity
// (materials) restart ranks 1 and 2 too. Rank 0 stops at 2 spp, so what the window shows after the edits is almost
// all the other ranks' samples: it must be the image of the scene as edited (saved by save-scene and rendered
// headless at 64 spp; their samples are other sample indices than a headless run's, so within noise, not bit for
// bit), their spp in the stats must be of the last epoch (the script waits for 40 spp in all; if their results never
// arrived, the run would time out), and quitting on rank 0 ends every rank (exit 0; a post that missed a rank,
// the last one included, leaves it running and the run times out). A rank that kept the old camera (tried), dropped
// its results, or whose results were merged wrongly fails.
TEST(Viewer, OffloadOrbitRestartsEveryRank) {
  REQUIRE_DISPLAY();
#ifndef PTVIEW_MPIEXEC
  GTEST_SKIP() << "built without MPI (PTVIEW_MPI=OFF)";
#else
  TempDir dir;
  std::string script = write_script(dir, "stop-at-spp 2\nwait-frames 1\norbit 35 10\nexpect-restart\n"
                                         "light-size 0.3 0.2\nexpect-restart\nlight-intensity 2\nexpect-restart\n"
                                         "wait-frames 2\nwait-spp 40\nsave " + dir / "viewer.pfm" + "\nsave-scene " +
                                         dir / "edited.json" + "\nscreenshot " + dir / "shot.png" + "\nquit\n");
  auto r = run_window({"--size", "96x64", "--max-depth", "6", "--threads", "1", "--script", script, "--stats-json",
                       dir / "stats.json"},
                      mpirun(3));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto stats = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(stats["ranks"], 3);
  ASSERT_EQ(stats["per_rank"].size(), 3u);
  EXPECT_EQ(stats["per_rank"][0]["spp"], 2);
  const int remote_spp = stats["per_rank"][1]["spp"].get<int>() + stats["per_rank"][2]["spp"].get<int>();
  EXPECT_GE(remote_spp, 38) << stats.dump();  // wait-spp 40 with rank 0 stopped at 2: no timing involved
  for (int k : {1, 2}) {
    if (stats["per_rank"][k]["spp"].get<int>() > 0) {
      EXPECT_GT(stats["per_rank"][k]["spp_per_s"].get<double>(), 0.0);
    }
  }
  EXPECT_EQ(stats["spp"], 2 + remote_spp);
  for (const std::string& name : {std::string("edited"), std::string("builtin:cornell-spheres")}) {
    const bool edited = name == "edited";
    auto h = test::run_ptview({edited ? dir / "edited.json" : name, "--frames", "64", "--size", "96x64",
                               "--max-depth", "6", "--out", dir / (edited ? "after.pfm" : "before.pfm")});
    ASSERT_EQ(h.exit_code, 0) << h.err;
  }
  Result<Image> viewer = load_image(dir / "viewer.pfm"), expected = load_image(dir / "after.pfm"),
                unedited = load_image(dir / "before.pfm");
  ASSERT_TRUE(viewer.ok() && expected.ok() && unedited.ok());
  const double d_after = mean_abs_diff(*viewer, *expected), d_before = mean_abs_diff(*viewer, *unedited);
  std::printf("offload: ranks 1 and 2 %d spp, |viewer - edited| %.4f, |viewer - unedited| %.4f\n", remote_spp, d_after,
              d_before);
  EXPECT_LT(d_after, 0.3 * d_before);
#endif
}

// Pause under mpirun holds every rank (view/offload.h): rank 0 stopped at 2 spp (an epoch begun after the stop),
// the other two rendering. Once paused (and their passes in flight have arrived, well within 1.5 s), two saves 1.5 s
// apart are the same image bit for bit, which they are not if a worker kept adding samples. Resumed, the workers
// add samples again: 1.5 s later the image has changed (rank 0 adds none).
TEST(Viewer, OffloadPauseHoldsEveryRank) {
  REQUIRE_DISPLAY();
#ifndef PTVIEW_MPIEXEC
  GTEST_SKIP() << "built without MPI (PTVIEW_MPI=OFF)";
#else
  TempDir dir;
  std::string script = write_script(dir,
                                    "stop-at-spp 2\norbit 10 0\nexpect-restart\nwait-spp 20\npause on\n"
                                    "wait-ms 1500\nsave " +
                                        dir / "a.pfm" + "\nwait-ms 1500\nsave " + dir / "b.pfm" +
                                        "\npause off\nwait-ms 1500\nsave " + dir / "c.pfm" + "\nquit\n");
  auto r = run_window(
      {"--size", "48x32", "--max-depth", "4", "--threads", "1", "--script", script, "--stats-json", dir / "stats.json"},
      mpirun(3));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string a = read_file(dir / "a.pfm"), b = read_file(dir / "b.pfm"), c = read_file(dir / "c.pfm");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "samples were added while paused";
  EXPECT_TRUE(b != c) << "no samples were added after the pause ended";
  auto stats = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(stats["per_rank"][0]["spp"], 2);
  EXPECT_GT(stats["spp"].get<int>(), 20);
#endif
}

// --quit-after-frames counts the frames of the scene as the script left it: a script that ends with an edit
// quits only once the edited scene has rendered that many frames, not on the frames the edit discarded.
TEST(Viewer, QuitAfterFramesCountsTheFramesOfTheLastEdit) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(dir, "wait-frames 3\nlight-scale 0.5\nexpect-restart\n");
  auto r = run_window({"--size", "64x48", "--max-depth", "3", "--quit-after-frames", "3", "--script", script,
                       "--stats-json", dir / "stats.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(read_file(dir / "stats.json"));
  EXPECT_EQ(j["epoch"].get<int>(), 2) << "the frames shown at exit are the edited scene's";
  EXPECT_GE(j["frames"].get<int>(), 3);
}

// An image the viewer cannot write (here a directory stands where the file should go, which stops even root) is
// one line on stderr naming it, and exit 2 once the window closes; the rest of the script still runs.
TEST(Viewer, AnImageThatCannotBeWrittenExitsTwoNamingIt) {
  REQUIRE_DISPLAY();
  TempDir dir;
  fs::create_directory(dir / "saved.png");
  fs::create_directory(dir / "shot.png");
  for (const std::string& command : {"save " + dir / "saved.png", "screenshot " + dir / "shot.png"}) {
    std::string script = write_script(dir, "wait-frames 1\n" + command + "\nwait-frames 2\nquit\n");
    auto r = run_window({"--size", "64x48", "--max-depth", "3", "--script", script, "--stats-json",
                         dir / "stats.json"});
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    const std::string path = command.substr(command.find(' ') + 1);
    EXPECT_NE(r.err.find("ptview: error: " + path), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "stats.json")) << "the stats are still written";
    fs::remove(dir / "stats.json");
  }
}

TEST(Viewer, WithoutADisplayExitsTwoSuggestingFrames) {
  TempDir dir;
  std::string cmd = "env -u DISPLAY -u WAYLAND_DISPLAY timeout 30 " + shell_quote(PTVIEW_EXE) + " >/dev/null 2>" +
                    shell_quote(dir / "err");
  int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::string err = read_file(dir / "err");
  EXPECT_NE(err.find("--frames"), std::string::npos) << err;
}

TEST(Viewer, MalformedScriptExitsTwoWithFileAndLine) {
  TempDir dir;
  std::string script = write_script(dir, "wait-frames 1\norbit 10\n");
  std::string cmd = "timeout 30 " + shell_quote(PTVIEW_EXE) + " --script " + shell_quote(script) + " >/dev/null 2>" +
                    shell_quote(dir / "err");
  int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_NE(read_file(dir / "err").find("script.txt:2:"), std::string::npos) << read_file(dir / "err");
}

}  // namespace
}  // namespace pt
