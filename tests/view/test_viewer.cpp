// The viewer tested as a person would use it: a real window under Xvfb, driven by scripted input through the same
// code paths as mouse and panels, checked through screenshots, saved images and the stats it writes at exit.
#include <gtest/gtest.h>
#include <unistd.h>
#include <stb_image.h>

#include <nlohmann/json.hpp>

#include "../app/run_exe.h"
#include "render/image.h"

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
RunResult run_window(const std::vector<std::string>& args) {
  std::string wrapper;
  if (have_xvfb()) wrapper = "xvfb-run -a -n " + std::to_string(100 + ::getpid() % 800) + " -s '-screen 0 1280x1024x24'";
  return test::run_ptview(args, 240, wrapper);
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

/// Mean absolute difference over the image part of the window (right of the panel column).
double mean_abs_diff(const Png& a, const Png& b) {
  if (a.rgb.size() != b.rgb.size() || a.rgb.empty()) return -1;
  double d = 0;
  size_t n = 0;
  for (int y = 0; y < a.h; ++y)
    for (int x = a.w / 2; x < a.w; ++x)
      for (int c = 0; c < 3; ++c, ++n) {
        size_t i = (size_t(y) * a.w + x) * 3 + c;
        d += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
      }
  return d / double(n);
}

std::string write_script(const TempDir& dir, const std::string& text) {
  std::string path = dir / "script.txt";
  std::ofstream(path) << text;
  return path;
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
}

TEST(Viewer, OrbitingChangesTheImage) {
  REQUIRE_DISPLAY();
  TempDir dir;
  std::string script = write_script(dir, "wait-frames 2\nscreenshot " + dir / "a.png" +
                                             "\norbit 35 10\nexpect-restart\nwait-frames 2\nscreenshot " +
                                             dir / "b.png" + "\nquit\n");
  auto r = run_window({"--size", "256x256", "--script", script});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  double d = mean_abs_diff(Png(dir / "a.png"), Png(dir / "b.png"));
  EXPECT_GT(d, 8.0);
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
  fs::path bunny = fs::path(PTVIEW_SOURCE_DIR) / ".." / "shared" / "models" / "stanford-bunny.obj";
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
  EXPECT_EQ(j["triangles"].get<size_t>(), expected);
  EXPECT_GT(j["bvh"]["nodes"].get<int>(), 100);
  auto [mean, var] = Png(dir / "loaded.png").image_stats();
  EXPECT_GT(var, 10.0);
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
