#pragma once
// Runs the real ptview executable and captures its exit code, stdout and stderr.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <span>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace pt::test {

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs PTVIEW_EXE with `args` (each quoted), with a timeout so a hang fails the test instead of blocking it.
/// `wrapper` goes between the timeout and the executable (e.g. "xvfb-run -a").
inline RunResult run_ptview(const std::vector<std::string>& args, int timeout_s = 300, const std::string& wrapper = "") {
  TempDir io;
  std::string cmd = "timeout " + std::to_string(timeout_s) + " " + wrapper + " " + shell_quote(PTVIEW_EXE);
  for (const std::string& a : args) cmd += " " + shell_quote(a);
  cmd += " >" + shell_quote(io / "out") + " 2>" + shell_quote(io / "err") + " </dev/null";
  int status = std::system(cmd.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(io / "out");
  r.err = read_file(io / "err");
  return r;
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  if (!s.empty() && s.back() != '\n') ++n;
  return n;
}

/// Command lines that must each fail with exit 2 and one stderr line mentioning `mentions`, writing nothing: the
/// bad-input contract, shared by every command-line test file.
struct BadArgs {
  std::vector<std::string> args;
  std::string mentions;
};
/// Runs every case; `out` is the output path the cases name (it must not appear), `dir` must stay empty.
inline void expect_bad_args_fail_cleanly(std::span<const BadArgs> cases, const std::string& out, const TempDir& dir) {
  for (const BadArgs& c : cases) {
    RunResult r = run_ptview(c.args, 60);
    std::string joined;
    for (auto& a : c.args) joined += a + " ";
    EXPECT_EQ(r.exit_code, 2) << joined << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << joined << "\n" << r.err;
    EXPECT_NE(r.err.find(c.mentions), std::string::npos) << joined << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << joined;
  }
  // Nothing half-written was left behind.
  for (auto& entry : std::filesystem::directory_iterator(dir.path)) ADD_FAILURE() << "left behind: " << entry.path();
}

}  // namespace pt::test
