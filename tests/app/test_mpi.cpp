// ptview under mpirun (src/dist): K ranks give the image of one process, the time limit holds across ranks, and
// failures end the run with one line, a non-zero exit and no output. Skipped when the build has no MPI.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <sstream>
#include <thread>

#include "render/image.h"
#include "run_exe.h"

namespace pt {
namespace {

using test::count_lines;
using test::read_file;
using test::run_ptview;
using test::shell_quote;
using test::TempDir;

#ifdef PTVIEW_MPIEXEC
constexpr bool kHaveMpi = true;
const char* const kMpiexec = PTVIEW_MPIEXEC;
#else
constexpr bool kHaveMpi = false;
const char* const kMpiexec = "";
#endif

#define SKIP_WITHOUT_MPI() \
  if (!kHaveMpi) GTEST_SKIP() << "built without MPI (PTVIEW_MPI=OFF)"

/// One application context of an mpirun command line: `ranks` processes of `prefix` ptview `args`.
struct Context {
  int ranks = 1;
  std::vector<std::string> args;
  std::string wdir = {};    ///< working directory of these ranks (empty: the current one)
  std::string prefix = {};  ///< a command run in front of ptview, e.g. "timeout -s KILL 2"
};

/// Runs `mpirun -q` (no notices of its own: stderr holds what ptview prints) with the given contexts. As root Open
/// MPI needs the ALLOW_RUN_AS_ROOT pair; in containers the vader single-copy mechanism may be unavailable. Under
/// AddressSanitizer, Open MPI's own allocations (in dlopen'ed, since unloaded plugins LeakSanitizer cannot
/// attribute) are not reported; our leaks are checked by every other test.
test::RunResult run_mpi(const std::vector<Context>& contexts, int timeout_s = 300) {
  TempDir io;
  std::string cmd = "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                    "OMPI_MCA_btl_vader_single_copy_mechanism=none ASAN_OPTIONS=detect_leaks=0 timeout " +
                    std::to_string(timeout_s) + " " + shell_quote(kMpiexec) + " -q --oversubscribe --bind-to none";
  for (size_t i = 0; i < contexts.size(); ++i) {
    const Context& c = contexts[i];
    if (i > 0) cmd += " :";
    cmd += " -np " + std::to_string(c.ranks);
    if (!c.wdir.empty()) cmd += " -wdir " + shell_quote(c.wdir);
    cmd += " " + c.prefix + " " + shell_quote(PTVIEW_EXE);
    for (const std::string& a : c.args) cmd += " " + shell_quote(a);
  }
  cmd += " >" + shell_quote(io / "out") + " 2>" + shell_quote(io / "err") + " </dev/null";
  int status = std::system(cmd.c_str());
  test::RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(io / "out");
  r.err = read_file(io / "err");
  return r;
}

test::RunResult run_mpi(int ranks, const std::vector<std::string>& args) { return run_mpi({Context{ranks, args}}); }

/// Largest per-pixel relative difference (channels of the linear mean).
double max_relative_difference(const Image& a, const Image& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    double x = a.rgb[i], y = b.rgb[i];
    if (x == y) continue;
    worst = std::max(worst, std::abs(x - y) / std::max(std::abs(x), std::abs(y)));
  }
  return worst;
}

bool no_files_in(const std::filesystem::path& dir) { return std::filesystem::is_empty(dir); }

// The contract: K ranks render disjoint sample ranges whose sum is the single-process film. A rank that rendered
// the wrong frames (another rank's samples, or frame = round) changes the image far beyond 1e-6.
TEST(Mpi, OneTwoThreeRanksGiveTheImageOfOneProcess) {
  SKIP_WITHOUT_MPI();
  TempDir dir;
  const std::vector<std::string> common = {"builtin:cornell-glass", "--frames", "5", "--spp-per-frame", "2",
                                           "--size", "40x30", "--threads", "1", "--sampler", "independent"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = common;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  auto one = run_ptview(with({"--out", dir / "one.pfm", "--stats-json", dir / "one.json"}));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  Result<Image> ref = load_image(dir / "one.pfm");
  ASSERT_TRUE(ref.ok()) << ref.error();
  auto one_stats = nlohmann::json::parse(read_file(dir / "one.json"));
  EXPECT_EQ(one_stats["ranks"], 1);
  EXPECT_EQ(one_stats["comm_ms"], 0.0);
  for (int k : {1, 2, 3}) {
    std::string out = dir / ("k" + std::to_string(k) + ".pfm"), stats = dir / ("k" + std::to_string(k) + ".json");
    auto r = run_mpi(k, with({"--out", out, "--stats-json", stats}));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    Result<Image> img = load_image(out);
    ASSERT_TRUE(img.ok()) << img.error();
    ASSERT_EQ(img->rgb.size(), ref->rgb.size());
    EXPECT_LE(max_relative_difference(*img, *ref), 1e-6) << k << " ranks";
    auto j = nlohmann::json::parse(read_file(stats));
    EXPECT_EQ(j["ranks"], k);
    EXPECT_EQ(j["spp"], 10);
    EXPECT_EQ(j["samples"], one_stats["samples"]);  // counters of every rank summed, no sample twice
    EXPECT_EQ(j["rays"], one_stats["rays"]);
    ASSERT_EQ(j["per_rank"].size(), size_t(k));
    int spp = 0;
    for (const auto& w : j["per_rank"]) spp += w["spp"].get<int>();
    EXPECT_EQ(spp, 10);
    if (k == 3) {  // frames 0,3 | 1,4 | 2 at 2 spp each
      EXPECT_EQ(j["per_rank"][0]["spp"], 4);
      EXPECT_EQ(j["per_rank"][2]["spp"], 2);
    }
  }
}

// Adaptive sampling across ranks: rank 0 tests convergence on the combined film at the single-process check points
// and broadcasts the active mask, so the ranks draw exactly the samples one process draws. The spp map is therefore
// identical (a convergence decision could only differ if a pixel's error landed within double rounding of the
// threshold; with ~1000 pixel tests per run that has a probability far below 1e-9), and the image equal within 1e-6.
// A rank rendering another offset (or every rank the same samples), or ranks deciding on their own films, changes
// the spp map. --max-spp alone (a last frame cut to 1 spp) is sharded the same way.
TEST(Mpi, AdaptiveSamplingAcrossRanksMatchesOneProcess) {
  SKIP_WITHOUT_MPI();
  TempDir dir;
  const std::vector<std::string> common = {"builtin:cornell-glass", "--size", "40x30", "--threads", "1"};
  for (const auto& extra : std::vector<std::vector<std::string>>{
           {"--noise-threshold", "0.1", "--max-spp", "200"},
           {"--noise-threshold", "0.2", "--min-spp", "8", "--spp-per-frame", "3", "--sampler", "independent",
            "--max-spp", "400"},
           {"--max-spp", "7", "--spp-per-frame", "2"}}) {
    const bool adaptive = extra[0] == "--noise-threshold";
    auto run = [&](int k) {
      std::string tag = dir / ("k" + std::to_string(k));
      std::vector<std::string> a = common;
      a.insert(a.end(), extra.begin(), extra.end());
      a.insert(a.end(), {"--out", tag + ".pfm", "--spp-map", tag + "_spp.pfm", "--stats-json", tag + ".json"});
      auto r = k == 0 ? run_ptview(a) : run_mpi(k, a);
      EXPECT_EQ(r.exit_code, 0) << r.err;
      return tag;
    };
    const std::string one = run(0);
    Result<Image> ref = load_image(one + ".pfm"), ref_spp = load_image(one + "_spp.pfm");
    ASSERT_TRUE(ref.ok() && ref_spp.ok());
    auto ref_stats = nlohmann::json::parse(read_file(one + ".json"));
    if (adaptive) {
      EXPECT_GT(ref_stats["converged_fraction"].get<double>(), 0.2) << extra[1];  // the test exercises stopping
      EXPECT_LT(ref_stats["spp_min"], ref_stats["spp_max"]);
    }
    for (int k : {2, 3}) {
      const std::string tag = run(k);
      Result<Image> img = load_image(tag + ".pfm"), spp = load_image(tag + "_spp.pfm");
      ASSERT_TRUE(img.ok() && spp.ok()) << k;
      EXPECT_EQ(spp->rgb, ref_spp->rgb) << extra[1] << ", " << k << " ranks";
      EXPECT_LE(max_relative_difference(*img, *ref), 1e-6) << extra[1] << ", " << k << " ranks";
      auto j = nlohmann::json::parse(read_file(tag + ".json"));
      for (const char* key : {"spp", "frames", "samples", "converged_fraction", "spp_min", "spp_max", "spp_mean",
                              "noise_threshold", "min_spp"})
        EXPECT_EQ(j[key], ref_stats[key]) << key << ", " << extra[1] << ", " << k << " ranks";
      EXPECT_NEAR(j["est_rel_mse"].get<double>(), ref_stats["est_rel_mse"].get<double>(),
                  1e-9 * ref_stats["est_rel_mse"].get<double>());
      ASSERT_EQ(j["per_rank"].size(), size_t(k));
      int spp_sum = 0;
      for (const auto& w : j["per_rank"]) {
        EXPECT_GT(w["spp"].get<int>(), 0);  // every rank took a share
        spp_sum += w["spp"].get<int>();
      }
      EXPECT_EQ(spp_sum, j["spp"].get<int>());
    }
  }
}

// CSV rows at every round (K frames) and at the end, with the error of the combined image, which is the
// single-process error at the same frame.
TEST(Mpi, ErrorCsvRowsAtRoundBoundariesMatchOneProcess) {
  SKIP_WITHOUT_MPI();
  TempDir dir;
  ASSERT_EQ(run_ptview({"--frames", "4", "--size", "24x24", "--out", dir / "ref.pfm"}).exit_code, 0);
  std::vector<std::string> args = {"--frames", "16", "--size", "24x24", "--threads", "1", "--reference",
                                   dir / "ref.pfm", "--out", dir / "x.pfm"};
  auto with_csv = [&](const std::string& csv) {
    std::vector<std::string> a = args;
    a.insert(a.end(), {"--error-csv", csv});
    return a;
  };
  ASSERT_EQ(run_ptview(with_csv(dir / "one.csv")).exit_code, 0);
  auto r = run_mpi(3, with_csv(dir / "three.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  struct Row {
    double seconds, rmse;
  };
  auto rows = [](const std::string& csv) {
    std::map<int, Row> out;  // by frame; columns frame,spp,seconds,rmse,...
    std::istringstream in(csv);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      const size_t c1 = line.find(','), c2 = line.find(',', c1 + 1), c3 = line.find(',', c2 + 1);
      out[std::stoi(line.substr(0, c1))] = {std::stod(line.substr(c2 + 1, c3 - c2 - 1)),
                                            std::stod(line.substr(c3 + 1))};
    }
    return out;
  };
  auto one = rows(read_file(dir / "one.csv")), three = rows(read_file(dir / "three.csv"));
  ASSERT_EQ(three.size(), 6u);
  double seconds = 0.0;
  for (int frame : {3, 6, 9, 12, 15, 16}) {
    ASSERT_TRUE(three.count(frame)) << "no row at frame " << frame;
    EXPECT_NEAR(three[frame].rmse, one[frame].rmse, 1e-6 * one[frame].rmse) << frame;
    EXPECT_GT(three[frame].seconds, seconds) << frame << ": the render time so far grows every round";
    seconds = three[frame].seconds;
  }
}

// The ranks agree on stopping (MPI_Allreduce every round): each renders the same number of frames, and the total
// is their sum. Any duration passes: only the agreement is checked.
TEST(Mpi, TimeLimitStopsEveryRankInTheSameRound) {
  SKIP_WITHOUT_MPI();
  TempDir dir;
  auto r = run_mpi(2, {"--time-limit", "0.3", "--size", "32x32", "--threads", "1", "--out", dir / "t.pfm",
                       "--stats-json", dir / "t.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(load_image(dir / "t.pfm").ok());
  auto j = nlohmann::json::parse(read_file(dir / "t.json"));
  ASSERT_EQ(j["per_rank"].size(), 2u);
  int a = j["per_rank"][0]["spp"], b = j["per_rank"][1]["spp"];
  EXPECT_GE(a, 1);
  EXPECT_EQ(a, b);
  EXPECT_EQ(j["spp"], a + b);
}

// The time limit is the user's wall clock: the run stops in the round where the first rank's limit has passed,
// not the last one's. A rank whose clock started later (a node that loaded the scene slower) is played here by a
// rank given a limit it would never reach: the run must still stop at the other's, every rank in the same round.
// Each rank reports the seconds it rendered itself.
TEST(Mpi, TheFirstRankPastTheTimeLimitStopsEveryRank) {
  SKIP_WITHOUT_MPI();
  TempDir dir;
  std::vector<std::string> args = {"--size", "32x32", "--threads", "1", "--out", dir / "t.pfm", "--stats-json",
                                   dir / "t.json", "--time-limit"};
  std::vector<std::string> late = args;
  args.push_back("0.3");
  late.push_back("100000");
  auto r = run_mpi({Context{1, args}, Context{1, late}}, 120);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(load_image(dir / "t.pfm").ok());
  auto j = nlohmann::json::parse(read_file(dir / "t.json"));
  ASSERT_EQ(j["per_rank"].size(), 2u);
  EXPECT_EQ(j["per_rank"][0]["spp"], j["per_rank"][1]["spp"]);
  const double s0 = j["per_rank"][0]["seconds"], s1 = j["per_rank"][1]["seconds"];
  EXPECT_GT(s0, 0.0);
  EXPECT_GT(s1, 0.0);
  EXPECT_NE(s0, s1) << "two clocks agree to the nanosecond only if one rank's figure was copied";
}

// Ranks on one machine share its cores: without --threads each takes its share (at least one).
TEST(Mpi, RanksOnOneMachineShareItsCores) {
  SKIP_WITHOUT_MPI();
  TempDir dir;
  auto r = run_mpi(2, {"--frames", "2", "--size", "16x16", "--out", dir / "t.pfm", "--stats-json", dir / "t.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(read_file(dir / "t.json"));
  const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_EQ(j["threads"], std::max(1, cores / 2));
}

// A scene that only rank 0's machine has (here: a relative path, rank 1 runs in another directory).
TEST(Mpi, SceneMissingOnAnotherRankIsOneClearLine) {
  SKIP_WITHOUT_MPI();
  TempDir a, b, out;
  std::filesystem::copy_file(std::string(PTVIEW_SOURCE_DIR) + "/assets/cornell.json", a / "s.json");
  std::vector<std::string> args = {"s.json", "--frames", "2", "--size", "16x16", "--out", out / "x.png"};
  auto r = run_mpi({Context{1, args, a.path.string()}, Context{1, args, b.path.string()}});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("rank 1 on "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("s.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("every node"), std::string::npos) << r.err;
  EXPECT_TRUE(no_files_in(out.path));
}

TEST(Mpi, BadInputIsOneLineFromRankZero) {
  SKIP_WITHOUT_MPI();
  TempDir out;
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--frames", "0", "--out", out / "x.png"},
           {"no-such-scene.json", "--frames", "1", "--out", out / "x.png"}}) {
    auto r = run_mpi(3, args);
    EXPECT_EQ(r.exit_code, 2) << args[0];
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_TRUE(no_files_in(out.path));
    // Rank 0's own error is the line one process prints (MPI may add a hint at its end), with no rank prefix: that
    // names the errors of other ranks.
    const std::string one = run_ptview(args).err;
    ASSERT_FALSE(one.empty());
    EXPECT_EQ(r.err.compare(0, one.size() - 1, one, 0, one.size() - 1), 0) << r.err << " against " << one;
  }
}

TEST(Mpi, HelpIsPrintedOnceByRankZero) {
  SKIP_WITHOUT_MPI();
  const auto r = run_mpi(3, {"--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, run_ptview({"--help"}).out) << "every rank parses the command line; only rank 0 prints";
  EXPECT_EQ(r.err, "");
}

// The films are summed in messages of at most 4 MiB: an 800 x 600 film's sums of doubles (11 MiB a buffer) take
// three, and every one must land at its own offset of rank 0's film.
TEST(Mpi, FilmsLargerThanOneMessageSumWhole) {
  SKIP_WITHOUT_MPI();
  TempDir dir;
  const std::vector<std::string> common = {"builtin:cornell", "--frames", "2", "--size", "800x600", "--max-depth",
                                           "2", "--threads", "1", "--sampler", "independent"};
  auto with = [&](const std::string& out) {
    std::vector<std::string> a = common;
    a.insert(a.end(), {"--out", out});
    return a;
  };
  ASSERT_EQ(run_ptview(with(dir / "one.pfm")).exit_code, 0);
  const Result<Image> ref = load_image(dir / "one.pfm");
  ASSERT_TRUE(ref.ok()) << ref.error();
  for (int k : {2, 3}) {
    const std::string out = dir / ("k" + std::to_string(k) + ".pfm");
    auto r = run_mpi(k, with(out));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Result<Image> img = load_image(out);
    ASSERT_TRUE(img.ok()) << img.error();
    ASSERT_EQ(img->rgb.size(), ref->rgb.size());
    EXPECT_LE(max_relative_difference(*img, *ref), 1e-6) << k << " ranks";
  }
}

// Without --frames rank 0 opens the viewer (the offload, src/view/offload.h); without a display it fails with the
// viewer's one line, and its end of the offload releases the other ranks, which wait for its epochs: no hang (the
// run_mpi timeout would make the exit code 124).
TEST(Mpi, ViewerWithoutADisplayEndsEveryRank) {
  SKIP_WITHOUT_MPI();
  TempDir out;
  auto r = run_mpi({Context{3, {"--size", "8x8", "--out", out / "x.png"}, "", "env -u DISPLAY -u WAYLAND_DISPLAY"}},
                   120);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("no display"), std::string::npos) << r.err;
  EXPECT_TRUE(no_files_in(out.path));
}

// Rank 1 is killed while the ranks render (5 s in: both are rendering by then, even under a sanitizer): mpirun
// stops rank 0, which says so in one line and has written nothing (outputs are written after the last reduction,
// atomically).
TEST(Mpi, RankThatDiesEndsTheRunWithoutOutput) {
  SKIP_WITHOUT_MPI();
  TempDir out;
  std::vector<std::string> args = {"--frames", "1000000", "--size", "16x16", "--threads", "1", "--out",
                                   out / "x.pfm", "--stats-json", out / "s.json"};
  auto r = run_mpi({Context{1, args}, Context{1, args, "", "timeout -s KILL 5"}});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("stopped by the MPI launcher"), std::string::npos) << r.err;
  EXPECT_TRUE(no_files_in(out.path));
}

}  // namespace
}  // namespace pt
