// The command-line contract checked by value on the real executable: PFM layout and orientation, the error CSV
// recomputed from the images, stats JSON values, every option with a valid value doing what it claims, and the
// progress line on a pseudo-terminal.
//
// Statistical checks (option convergence) use a z-score of the image-mean difference below 6: a two-sided normal
// false-alarm rate of 2e-9 per check, 1e-8 for the file. Everything else is deterministic.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <pty.h>
#include <stb/stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

#include "app/app.h"
#include "render/image.h"
#include "render/light.h"
#include "run_exe.h"

namespace pt {
namespace {

using test::read_file;
using test::run_ptview;
using test::TempDir;

/// Black background, one emissive square (radiance 1, facing the camera) in the upper left of the view.
const char* kUpperLeftLight = R"({
  "camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40},
  "background": [0, 0, 0],
  "materials": {"light": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [1, 1, 1]}},
  "shapes": [{"type": "quad", "corner": [-0.9, 0.1, 0], "edge1": [0.8, 0, 0], "edge2": [0, 0.8, 0],
              "material": "light"}]
})";

std::string write_scene(const TempDir& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return dir / name;
}

TEST(CliContract, PfmIsTheLinearMeanWithTheRightLayout) {
  TempDir dir;
  const std::string scene = write_scene(dir, "ul.json", kUpperLeftLight);
  const int W = 24, H = 16;
  auto r = run_ptview({scene, "--frames", "2", "--size", "24x16", "--out", dir / "x.pfm", "--exposure", "3",
                       "--tonemap", "aces"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto plain = run_ptview({scene, "--frames", "2", "--size", "24x16", "--out", dir / "plain.pfm"});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const std::string pfm = read_file(dir / "x.pfm");
  // Exposure and tonemap are display settings: the PFM is the same bytes without them.
  EXPECT_EQ(pfm, read_file(dir / "plain.pfm"));
  const std::string header = "PF\n24 16\n-1.0\n";
  ASSERT_EQ(pfm.rfind(header, 0), 0u);
  ASSERT_EQ(pfm.size(), header.size() + size_t(W) * H * 12);
  // Raw layout: little-endian floats, rows bottom to top. The light is in the upper left of the image, so it is
  // in the LAST rows of the file, left half; everything else is exactly 0.
  double quadrant[2][2] = {};  // [image top?][left?]
  for (int file_row = 0; file_row < H; ++file_row)
    for (int x = 0; x < W; ++x) {
      float v;
      std::memcpy(&v, pfm.data() + header.size() + (size_t(file_row) * W + x) * 12, 4);
      int image_row = H - 1 - file_row;
      quadrant[image_row < H / 2][x < W / 2] += v;
    }
  EXPECT_GT(quadrant[1][1], 20.0);  // top left: the light (linear radiance 1 per covered pixel)
  EXPECT_EQ(quadrant[1][0], 0.0);
  EXPECT_EQ(quadrant[0][1], 0.0);
  EXPECT_EQ(quadrant[0][0], 0.0);
  // The loader agrees (top row first in memory).
  Result<Image> img = load_image(dir / "x.pfm");
  ASSERT_TRUE(img.ok()) << img.error();
  EXPECT_GT(img->at(W / 4, H / 4).x, 0.5f);
  EXPECT_EQ(img->at(W - 1 - W / 4, H - 1 - H / 4).x, 0.0f);
}

/// Parses a CSV with a header into rows of name -> value (columns found by name, not position).
std::vector<std::map<std::string, double>> parse_csv(const std::string& text) {
  std::vector<std::map<std::string, double>> rows;
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> names;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;  // keeps empty cells, a trailing one too ("1,1,...,0.1," has an empty last cell)
    size_t start = 0;
    for (size_t comma; (comma = l.find(',', start)) != std::string::npos; start = comma + 1)
      out.push_back(l.substr(start, comma - start));
    out.push_back(l.substr(start));
    return out;
  };
  if (std::getline(in, line)) names = split(line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells = split(line);
    EXPECT_EQ(cells.size(), names.size()) << line;
    std::map<std::string, double> row;
    for (size_t i = 0; i < cells.size() && i < names.size(); ++i)
      if (!cells[i].empty()) row[names[i]] = std::stod(cells[i]);  // empty: unknown (est_rel_mse at 1 spp)
    rows.push_back(row);
  }
  return rows;
}

/// rmse and rel_mse as the README defines them, in double, written out independently of compare_images.
std::pair<double, double> readme_errors(const Image& x, const Image& ref) {
  double se = 0, rel = 0;
  const size_t n = x.rgb.size();
  for (size_t i = 0; i < n; ++i) {
    double d = double(x.rgb[i]) - double(ref.rgb[i]);
    se += d * d;
    rel += d * d / (double(ref.rgb[i]) * ref.rgb[i] + 0.01);
  }
  return {std::sqrt(se / n), rel / n};
}

TEST(CliContract, ErrorCsvAgainstAReference) {
  TempDir dir;
  ASSERT_EQ(run_ptview({"--frames", "8", "--size", "24x20", "--seed", "5", "--out", dir / "ref.pfm"}).exit_code, 0);
  auto r = run_ptview({"--frames", "4", "--size", "24x20", "--out", dir / "x.pfm", "--reference", dir / "ref.pfm",
                       "--error-csv", dir / "e.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto rows = parse_csv(read_file(dir / "e.csv"));
  ASSERT_EQ(rows.size(), 4u);
  for (size_t i = 0; i < rows.size(); ++i) {
    ASSERT_TRUE(rows[i].count("rmse") && rows[i].count("rel_mse") && rows[i].count("frame") && rows[i].count("spp"));
    EXPECT_EQ(rows[i]["frame"], double(i + 1));
    EXPECT_EQ(rows[i]["spp"], double(i + 1));
    EXPECT_GT(rows[i]["rmse"], 0.0) << "another seed: the images differ";
    EXPECT_GT(rows[i]["rel_mse"], 0.0);
    // The estimate needs both halves of the samples: an empty cell at 1 spp, a positive number after.
    if (i == 0) {
      EXPECT_EQ(rows[i].count("est_rel_mse"), 0u);
    } else {
      EXPECT_GT(rows[i]["est_rel_mse"], 0.0);
    }
  }
  // The last row is the error of the written image, recomputed here from the two files.
  Result<Image> x = load_image(dir / "x.pfm"), ref = load_image(dir / "ref.pfm");
  ASSERT_TRUE(x.ok() && ref.ok());
  auto [rmse, rel] = readme_errors(*x, *ref);
  ASSERT_GT(rmse, 0.0);
  EXPECT_NEAR(rows.back()["rmse"], rmse, 1e-6 * rmse);
  EXPECT_NEAR(rows.back()["rel_mse"], rel, 1e-6 * rel);
  // Against itself the error is exactly zero.
  r = run_ptview({"--frames", "8", "--size", "24x20", "--seed", "5", "--out", dir / "y.pfm", "--reference",
                  dir / "ref.pfm", "--error-csv", dir / "self.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto self = parse_csv(read_file(dir / "self.csv"));
  ASSERT_EQ(self.size(), 8u);
  EXPECT_EQ(self.back()["rmse"], 0.0);
  EXPECT_EQ(self.back()["rel_mse"], 0.0);
  EXPECT_GT(self.front()["rmse"], 0.0);
}

TEST(CompareImages, HandBuiltImages) {
  Image a(2, 1), b(2, 1);
  // Identical: zero.
  EXPECT_EQ(compare_images(a, b).rmse, 0.0);
  EXPECT_EQ(compare_images(a, b).rel_mse, 0.0);
  // One channel off by 1 against a reference of 0: squared errors {1, 0, 0, 0, 0, 0}.
  a.rgb = {1, 0, 0, 0, 0, 0};
  ImageError e = compare_images(a, b);
  EXPECT_NEAR(e.rmse, std::sqrt(1.0 / 6.0), 1e-12);
  EXPECT_NEAR(e.rel_mse, (1.0 / 0.01) / 6.0, 1e-9);
  // Reference 2 everywhere, image 2 except one channel at 5 and one at 1: errors 3 and -1.
  b.rgb = {2, 2, 2, 2, 2, 2};
  a.rgb = {5, 2, 2, 2, 1, 2};
  e = compare_images(a, b);
  EXPECT_NEAR(e.rmse, std::sqrt(10.0 / 6.0), 1e-12);
  EXPECT_NEAR(e.rel_mse, (9.0 + 1.0) / 4.01 / 6.0, 1e-12);
  // Not symmetric: the reference is the denominator.
  EXPECT_NE(compare_images(b, a).rel_mse, e.rel_mse);
}

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(read_file(path)); }

TEST(CliContract, StatsJsonHasTheContractKeys) {
  TempDir dir;
  const int W = 32, H = 24, frames = 3, spf = 2;
  auto r = run_ptview({"--frames", "3", "--spp-per-frame", "2", "--size", "32x24", "--out", dir / "x.png",
                       "--stats-json", dir / "s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = read_json(dir / "s.json");
  for (const char* key : {"spp", "seconds", "rays", "mrays_per_s", "nonfinite_samples", "bvh", "skipped"})
    ASSERT_TRUE(j.contains(key)) << key;
  for (const char* key : {"build_ms", "nodes", "sah_cost", "depth"}) ASSERT_TRUE(j["bvh"].contains(key)) << key;
  EXPECT_EQ(j["spp"], frames * spf);
  const double rays = j["rays"].get<double>(), seconds = j["seconds"].get<double>();
  ASSERT_GT(seconds, 0.0);
  EXPECT_NEAR(j["mrays_per_s"].get<double>(), rays / seconds / 1e6, 1e-9 * rays / seconds / 1e6);
  // One camera ray per pixel sample; the total is camera + bounce + shadow rays.
  const auto& kinds = j["rays_by_kind"];
  EXPECT_EQ(kinds["camera"].get<double>(), double(W) * H * frames * spf);
  EXPECT_EQ(kinds["camera"].get<double>() + kinds["bounce"].get<double>() + kinds["shadow"].get<double>(), rays);
  EXPECT_EQ(j["samples"].get<double>(), double(W) * H * frames * spf);
  EXPECT_GT(kinds["bounce"].get<double>(), 0.0);
  EXPECT_GT(kinds["shadow"].get<double>(), 0.0);
  // BVH depth: a whole number, at least what a perfectly balanced binary tree of that many nodes needs, at most
  // the node count.
  ASSERT_TRUE(j["bvh"]["depth"].is_number_integer());
  const double depth = j["bvh"]["depth"].get<double>();
  const double binary_nodes = j["bvh"]["binary_nodes"].get<double>();
  ASSERT_GT(binary_nodes, 1.0);
  EXPECT_GE(depth + 1, std::log2(binary_nodes + 1) - 1e-9);
  EXPECT_LE(depth, binary_nodes);
  EXPECT_GT(j["bvh"]["nodes"].get<int>(), 0);
  EXPECT_GT(j["skipped"]["light_sampling_specular"].get<double>(), 0);  // glass and mirror spheres
  // Every sample's path ends for one of the reasons listed.
  double ended = 0.0;
  for (const char* key : {"paths_escaped", "paths_ended_max_depth", "paths_ended_roulette", "paths_ended_absorbed"}) {
    ASSERT_TRUE(j["skipped"].contains(key)) << key;
    ended += j["skipped"][key].get<double>();
  }
  EXPECT_EQ(ended, j["samples"].get<double>());
}

/// Image-mean difference of two PFMs in units of its standard error, estimated from the per-pixel differences
/// (pixels are independent estimates; under "same expected image" every difference has mean 0).
double mean_difference_z(const Image& a, const Image& b) {
  const size_t n = size_t(a.width) * a.height;
  double s = 0, s2 = 0;
  for (size_t p = 0; p < n; ++p) {
    double d = luminance(a.at(int(p % a.width), int(p / a.width))) - luminance(b.at(int(p % b.width), int(p / b.width)));
    s += d;
    s2 += d * d;
  }
  double mean = s / n, var = std::max(1e-30, s2 / n - mean * mean);
  return mean / std::sqrt(var / n);
}

TEST(CliContract, OptionsWithValidValuesChangeWhatTheyClaimAndConverge) {
  TempDir dir;
  const std::vector<std::string> common = {"builtin:cornell", "--frames", "4", "--spp-per-frame", "8", "--size",
                                           "32x32", "--max-depth", "6"};
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    for (std::string a : {std::string("--out"), dir / (name + ".pfm"), std::string("--stats-json"), dir / (name + ".json")})
      args.push_back(a);
    auto r = run_ptview(args);
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    Result<Image> img = load_image(dir / (name + ".pfm"));
    EXPECT_TRUE(img.ok()) << name;
    return std::make_pair(img.ok() ? *img : Image(), read_json(dir / (name + ".json")));
  };
  auto [base, base_stats] = run("base", {"--integrator", "mis"});
  EXPECT_EQ(base_stats["integrator"], "mis");
  EXPECT_EQ(base_stats["sampler"], "sobol");
  EXPECT_EQ(base_stats["light_sampling"], "auto");
  struct Variant {
    std::string name;
    std::vector<std::string> args;
    std::string key, value;
    std::string against = "base";  ///< the run whose bytes it must change
  };
  // On this scene automatic light sampling leaves the first vertex to area sampling (its pilot finds that solid
  // angle does not pay here: stats auto_first_vertex), so area is told apart from solid-angle, not from auto.
  const Variant variants[] = {
      {"default", {}, "integrator", "auto"},  // auto picks nee here: lights are not sampled by area
      {"independent", {"--sampler", "independent", "--integrator", "mis"}, "sampler", "independent"},
      {"nee", {"--integrator", "nee"}, "integrator", "nee"},
      {"bsdf", {"--integrator", "bsdf"}, "integrator", "bsdf"},
      {"solid-angle", {"--light-sampling", "solid-angle", "--integrator", "mis"}, "light_sampling", "solid-angle"},
      {"area", {"--light-sampling", "area", "--integrator", "mis"}, "light_sampling", "area", "solid-angle"},
  };
  EXPECT_EQ(base_stats["auto_first_vertex"]["min_spread"], kAutoMinSpreadDeep);
  std::map<std::string, Image> images{{"base", base}};
  for (const Variant& v : variants) {
    auto [img, stats] = run(v.name, v.args);
    images[v.name] = img;
    EXPECT_EQ(stats[v.key], v.value) << v.name;
    // It changes the samples (an option parsed and then ignored would give the same bytes)...
    EXPECT_NE(img.rgb, images[v.against].rgb) << v.name << " made no difference";
    // ...and still estimates the same image.
    EXPECT_LT(std::abs(mean_difference_z(img, base)), 6.0) << v.name;
    // What each claims, in the counters.
    const double shadow = stats["rays_by_kind"]["shadow"].get<double>();
    if (v.name == "bsdf") {
      EXPECT_EQ(shadow, 0.0) << "BSDF sampling only casts no shadow rays";
    } else {
      EXPECT_GT(shadow, 0.0) << v.name;
    }
  }
}

double png_mean(const std::string& path) {
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 3);
  if (!data) return -1.0;
  double s = 0;
  for (int i = 0; i < w * h * 3; ++i) s += data[i];
  stbi_image_free(data);
  return s / (w * h * 3);
}

TEST(CliContract, TonemapAndExposureChangeThePngNotThePfm) {
  TempDir dir;
  const std::vector<std::string> common = {"builtin:cornell", "--frames", "1", "--size", "24x24"};
  auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = run_ptview(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  };
  run({"--out", dir / "base.png"});
  run({"--out", dir / "bright.png", "--exposure", "2"});
  run({"--out", dir / "dark.png", "--exposure", "-2"});
  run({"--out", dir / "aces.png", "--tonemap", "aces"});
  run({"--out", dir / "reinhard.png", "--tonemap", "reinhard"});
  run({"--out", dir / "base.pfm"});
  run({"--out", dir / "display.pfm", "--exposure", "2", "--tonemap", "reinhard"});
  const double base = png_mean(dir / "base.png");
  ASSERT_GT(base, 5.0);
  EXPECT_GT(png_mean(dir / "bright.png"), base + 5.0);
  EXPECT_LT(png_mean(dir / "dark.png"), base - 5.0);
  for (const char* tm : {"aces.png", "reinhard.png"}) EXPECT_NE(read_file(dir / tm), read_file(dir / "base.png")) << tm;
  EXPECT_NE(read_file(dir / "aces.png"), read_file(dir / "reinhard.png"));
  EXPECT_EQ(read_file(dir / "display.pfm"), read_file(dir / "base.pfm"));
}

TEST(CliContract, TimeLimitWithoutFrames) {
  TempDir dir;
  auto r = run_ptview({"--size", "16x16", "--time-limit", "0.3", "--out", dir / "x.pfm", "--stats-json",
                       dir / "s.json"}, 120);
  ASSERT_EQ(r.exit_code, 0) << r.err;  // headless: no display needed, no window opened
  auto j = read_json(dir / "s.json");
  EXPECT_GE(j["frames"].get<int>(), 1);
  EXPECT_EQ(j["spp"].get<int>(), j["frames"].get<int>());
  Result<Image> img = load_image(dir / "x.pfm");
  ASSERT_TRUE(img.ok()) << img.error();
  EXPECT_EQ(img->width, 16);
}

TEST(CliContract, StdoutNamesTheImageOnlyWhenItsNameWasNotGiven) {
  // Without --out the image goes to ./ptview.png, which stdout says; with --out stdout stays empty for scripts.
  TempDir dir;
  auto named = run_ptview({"--size", "8x8", "--frames", "1", "--out", dir / "x.png"});
  ASSERT_EQ(named.exit_code, 0) << named.err;
  EXPECT_EQ(named.out, "");
  auto unnamed = run_ptview({"--size", "8x8", "--frames", "1"}, 300, "env -C " + test::shell_quote(dir.path.string()));
  ASSERT_EQ(unnamed.exit_code, 0) << unnamed.err;
  EXPECT_TRUE(unnamed.out.starts_with("ptview: wrote ptview.png (1 spp, ")) << unnamed.out;
  EXPECT_EQ(test::count_lines(unnamed.out), 1);
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.path / "ptview.png"));
}

TEST(CliContract, AnOutputThatFailsAtTheEndExitsTwoWithOneLine) {
  // /proc exists (the options' checks pass) but takes no new files, so the write fails after the render: the
  // image, written first, is whole, and the failing output gives exit 2 and one line naming it.
  if (!std::filesystem::is_directory("/proc/self")) GTEST_SKIP() << "no /proc";
  const std::pair<const char*, std::string> cases[] = {{"--error-map", "/proc/ptview-test.pfm"},
                                                        {"--spp-map", "/proc/ptview-test.pfm"},
                                                        {"--stats-json", "/proc/ptview-test.json"},
                                                        {"--error-csv", "/proc/ptview-test.csv"}};
  for (const auto& [option, target] : cases) {
    SCOPED_TRACE(option);
    TempDir dir;
    auto r = run_ptview({"--size", "8x8", "--frames", "2", "--out", dir / "x.pfm", option, target});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(target), std::string::npos) << r.err;
    EXPECT_TRUE(load_image(dir / "x.pfm").ok());
  }
  // The image itself failing the same way.
  auto r = run_ptview({"--size", "8x8", "--frames", "2", "--out", "/proc/ptview-test.pfm"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("/proc/ptview-test.pfm"), std::string::npos) << r.err;
}

TEST(CliContract, ProgressLineOnATerminal) {
  TempDir dir;
  int master = -1;
  pid_t pid = ::forkpty(&master, nullptr, nullptr, nullptr);
  ASSERT_GE(pid, 0) << std::strerror(errno);
  if (pid == 0) {
    // Child: stdin, stdout and stderr are the pseudo-terminal. `timeout` bounds a hang.
    const std::string out = dir / "x.png";
    ::execlp("timeout", "timeout", "120", PTVIEW_EXE, "--frames", "3", "--size", "16x16", "--out", out.c_str(),
             static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::string text;
  char buf[4096];
  for (;;) {
    ssize_t n = ::read(master, buf, sizeof buf);
    if (n <= 0) break;  // EIO once the child has exited
    text.append(buf, size_t(n));
  }
  ::close(master);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 0) << text;
  // One line rewritten with \r per frame, finished by a newline: frame, spp, spp/s, Mrays/s.
  for (const char* part : {"frame 1/3", "frame 3/3", "spp 3", "spp/s", "Mrays/s", "\r"})
    EXPECT_NE(text.find(part), std::string::npos) << "missing '" << part << "' in: " << text;
  EXPECT_NE(text.find("ETA"), std::string::npos) << text;
  EXPECT_TRUE(std::filesystem::exists(dir / "x.png"));
}

}  // namespace
}  // namespace pt
