// The convergence options on the real executable: the error CSV without a reference, error and spp maps, adaptive
// sampling's stopping rule and stats, determinism across thread counts, and one-line errors for bad values.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

#include "render/image.h"
#include "run_exe.h"

namespace pt {
namespace {

using test::count_lines;
using test::read_file;
using test::run_ptview;
using test::TempDir;
using test::BadArgs;
using test::expect_bad_args_fail_cleanly;

TEST(ConvergenceCli, ErrorCsvWithoutAReferenceHasEmptyReferenceColumns) {
  TempDir dir;
  auto r = run_ptview({"--frames", "8", "--size", "16x16", "--out", dir / "x.pfm", "--error-csv", dir / "e.csv",
                       "--stats-json", dir / "s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string csv = read_file(dir / "e.csv");
  EXPECT_EQ(csv.rfind("frame,spp,seconds,rmse,rel_mse,est_rel_mse\n", 0), 0u) << csv;
  EXPECT_EQ(count_lines(csv), 9);
  // Frame 1: the second half of the estimator is still empty (unknown); from frame 2 on it is a number.
  EXPECT_NE(csv.find("\n1,1,"), std::string::npos);
  std::string last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
  EXPECT_EQ(last.rfind("8,8,", 0), 0u) << last;
  size_t empties = last.rfind(",,");
  ASSERT_NE(empties, std::string::npos) << last;
  double est = std::stod(last.substr(empties + 2));
  EXPECT_GT(est, 0.0);
  auto j = nlohmann::json::parse(read_file(dir / "s.json"));
  EXPECT_NEAR(j["est_rel_mse"].get<double>(), est, 1e-6 * est);
  EXPECT_EQ(j["spp_min"], 8);
  EXPECT_EQ(j["spp_max"], 8);
  EXPECT_EQ(j["converged_fraction"], 0.0);
}

TEST(ConvergenceCli, AdaptiveRunStopsWhenConvergedAndWritesMaps) {
  TempDir dir;
  auto r = run_ptview({"builtin:cornell-glass", "--size", "24x24", "--noise-threshold", "0.3", "--min-spp", "8",
                       "--max-spp", "4096", "--out", dir / "x.pfm", "--stats-json", dir / "s.json", "--error-map",
                       dir / "err.pfm", "--spp-map", dir / "spp.exr", "--spp-per-frame", "4"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(read_file(dir / "s.json"));
  EXPECT_EQ(j["converged_fraction"], 1.0);
  EXPECT_LT(j["spp_max"].get<int>(), 4096);  // ended by convergence, not by --max-spp
  EXPECT_EQ(j["spp"], j["spp_max"]);         // and in the round the last pixel stopped
  EXPECT_GE(j["spp_min"].get<int>(), 8);
  EXPECT_EQ(j["min_spp"], 8);
  EXPECT_EQ(j["noise_threshold"], 0.3);
  Result<Image> err = load_image(dir / "err.pfm");
  Result<Image> spp = load_image(dir / "spp.exr");
  ASSERT_TRUE(err && spp);
  ASSERT_EQ(err->width, 24);
  ASSERT_EQ(spp->height, 24);
  double total = 0;
  float lo = 1e30f, hi = 0;
  for (size_t i = 0; i < spp->rgb.size(); i += 3) {
    total += spp->rgb[i];
    lo = std::min(lo, spp->rgb[i]);
    hi = std::max(hi, spp->rgb[i]);
    EXPECT_LT(err->rgb[i], 0.3f);  // every pixel converged below the threshold
  }
  EXPECT_EQ(lo, j["spp_min"].get<float>());
  EXPECT_EQ(hi, j["spp_max"].get<float>());
  EXPECT_NEAR(total / (24 * 24), j["spp_mean"].get<double>(), 1e-3);
}

TEST(ConvergenceCli, MaxSppEndsTheRun) {
  TempDir dir;
  auto r = run_ptview({"--max-spp", "6", "--spp-per-frame", "4", "--size", "8x8", "--out", dir / "x.pfm",
                       "--stats-json", dir / "s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(read_file(dir / "s.json"));
  EXPECT_EQ(j["spp"], 6);
  EXPECT_EQ(j["spp_min"], 6);
}

TEST(ConvergenceCli, AdaptiveImageIsIdenticalForAnyThreadCount) {
  TempDir dir;
  std::string files[3];
  int k = 0;
  for (const char* threads : {"1", "2", "3"}) {
    files[k] = dir / (std::string("t") + threads + ".pfm");
    auto r = run_ptview({"builtin:cornell-glass", "--size", "20x20", "--noise-threshold", "0.2", "--max-spp", "64",
                         "--threads", threads, "--out", files[k], "--spp-map", dir / (std::string("s") + threads + ".pfm")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ++k;
  }
  EXPECT_EQ(read_file(files[0]), read_file(files[1]));
  EXPECT_EQ(read_file(files[0]), read_file(files[2]));
  EXPECT_EQ(read_file(dir / "s1.pfm"), read_file(dir / "s3.pfm"));
}

// Without --error-csv the headless mode renders up to 16 frames per pass (frames_per_pass in app/headless.cpp);
// with it, one frame per pass, for a row per frame. The image and the frame and sample counts must not differ:
// whole frames, a --max-spp that cuts the last frame, and adaptive sampling, whose checks end passes.
TEST(ConvergenceCli, PassesOfSeveralFramesGiveTheImageOfFrameByFrame) {
  TempDir dir;
  const std::vector<std::vector<std::string>> runs = {
      {"--frames", "37", "--spp-per-frame", "3"},
      {"--max-spp", "45", "--spp-per-frame", "4"},
      {"builtin:cornell-glass", "--noise-threshold", "0.2", "--min-spp", "6", "--max-spp", "200", "--spp-per-frame",
       "2"},
  };
  int k = 0;
  for (const auto& run : runs) {
    std::string image[2], stats[2];
    for (int per_frame = 0; per_frame < 2; ++per_frame) {
      std::vector<std::string> args = run;
      image[per_frame] = dir / ("i" + std::to_string(k) + std::to_string(per_frame) + ".pfm");
      stats[per_frame] = dir / ("s" + std::to_string(k) + std::to_string(per_frame) + ".json");
      for (std::string a : {"--size", "20x16", "--threads", "2", "--out", image[per_frame].c_str(), "--stats-json",
                            stats[per_frame].c_str()})
        args.push_back(a);
      if (per_frame) args.insert(args.end(), {"--error-csv", dir / "e.csv"});
      auto r = run_ptview(args);
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    SCOPED_TRACE("run " + std::to_string(k));
    EXPECT_EQ(read_file(image[0]), read_file(image[1]));
    auto passes = nlohmann::json::parse(read_file(stats[0])), frames = nlohmann::json::parse(read_file(stats[1]));
    for (const char* key : {"frames", "spp", "spp_min", "spp_max", "spp_mean", "samples", "rays", "converged_fraction"})
      EXPECT_EQ(passes[key], frames[key]) << key;
    EXPECT_EQ(count_lines(read_file(dir / "e.csv")), frames["frames"].get<int>() + 1);
    ++k;
  }
}

TEST(ConvergenceCli, BadValuesExitTwoWithOneLine) {
  TempDir dir;
  const std::string out = dir / "x.png";
  const BadArgs cases[] = {
      {{"--frames", "1", "--noise-threshold", "0", "--out", out}, "--noise-threshold"},
      {{"--frames", "1", "--noise-threshold", "-0.1", "--out", out}, "--noise-threshold"},
      {{"--frames", "1", "--noise-threshold", "nan", "--out", out}, "--noise-threshold"},
      {{"--frames", "1", "--noise-threshold", "2", "--out", out}, "--noise-threshold"},
      {{"--frames", "1", "--noise-threshold", "abc", "--out", out}, "--noise-threshold"},
      {{"--frames", "1", "--min-spp", "16", "--out", out}, "--min-spp"},
      {{"--frames", "1", "--noise-threshold", "0.1", "--min-spp", "0", "--out", out}, "--min-spp"},
      {{"--frames", "1", "--noise-threshold", "0.1", "--min-spp", "x", "--out", out}, "--min-spp"},
      {{"--frames", "1", "--noise-threshold", "0.1", "--min-spp", "16777217", "--out", out}, "--min-spp"},
      {{"--max-spp", "0", "--out", out}, "--max-spp"},
      {{"--max-spp", "-5", "--out", out}, "--max-spp"},
      {{"--max-spp", "99999999999", "--out", out}, "--max-spp"},
      {{"--frames", "1", "--error-map", dir / "e.png", "--out", out}, "--error-map"},
      {{"--frames", "1", "--spp-map", dir / "nodir/s.pfm", "--out", out}, "nodir"},
      {{"--error-map", dir / "e.pfm"}, "--error-map"},  // not headless
  };
  expect_bad_args_fail_cleanly(cases, out, dir);
}

}  // namespace
}  // namespace pt
