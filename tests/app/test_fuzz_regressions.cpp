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
#include "scene/load.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }

TEST(FuzzRegressions, EveryKeptCrashIsHandled) {
  test::TempDir dir;
  int n = 0;
  for (auto& e : fs::directory_iterator(fs::path(PTVIEW_TEST_DATA) / "bad")) {
    std::string name = e.path().filename().string();
    if (name.rfind("fuzz-", 0) != 0) continue;
    ++n;
    std::string text = test::read_file(e.path());
    if (name.rfind("fuzz-fuzz_json", 0) == 0) {
      Result<Scene> r = parse_json_scene(text, dir / "fuzz.json");
      if (!r.ok()) {
        EXPECT_TRUE(one_line(r.error())) << name << ": " << r.error();
      }
    } else if (name.rfind("fuzz-fuzz_obj", 0) == 0) {
      size_t split = text.find("\nnewmtl");
      std::ofstream(dir / "m.obj", std::ios::binary) << "mtllib m.mtl\n" << text.substr(0, split);
      std::ofstream(dir / "m.mtl", std::ios::binary) << (split == std::string::npos ? "" : text.substr(split));
      Result<Scene> r = load_scene(dir / "m.obj");
      if (!r.ok()) {
        EXPECT_TRUE(one_line(r.error())) << name << ": " << r.error();
      }
    } else if (name.rfind("fuzz-fuzz_render", 0) == 0) {
      EXPECT_EQ(fuzz::check_render_input(text, dir.path), "") << name;
    } else if (name.rfind("fuzz-fuzz_cli", 0) == 0) {
      std::vector<std::string> args = fuzz::split_args(text.data(), text.size());
      std::vector<const char*> argv;
      for (const std::string& a : args) argv.push_back(a.c_str());
      ParseOutcome out = parse_command_line(int(argv.size()), argv.data());
      EXPECT_TRUE(out.options || out.exit_code == 0 || out.exit_code == 2) << name;
    }
  }
  std::cout << n << " fuzz regression inputs\n";
}

}  // namespace
}  // namespace pt
