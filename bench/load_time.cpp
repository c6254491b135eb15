// Scene loading alone (no BVH, no rendering): wall time of load_scene per file, best of --reps, with the
// triangle count. For peak memory run it under /usr/bin/time -v with --reps 1.
// Usage: bench_load_time [--reps N] FILE...   (large inputs: bench/gen_large_gltf.py)
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "scene/load.h"

int main(int argc, char** argv) {
  int reps = 3;
  std::vector<std::string> files;
  CLI::App app{"Scene loading alone (no BVH, no rendering): wall time of load_scene per file, best of --reps.",
               "bench_load_time"};
  app.add_option("--reps", reps, "Loads per file, the best reported (default 3)")->check(CLI::Range(1, 1000));
  app.add_option("files", files, "Scene files (.obj, .gltf, .glb, .json)")->required();
  if (std::optional<int> exit_code = bench::parse_command_line(app, argc, argv)) return *exit_code;
  std::printf("%-40s %12s %10s\n", "file", "triangles", "best_ms");
  for (const std::string& f : files) {
    double best = 1e300;
    size_t triangles = 0;
    for (int r = 0; r < reps; ++r) {
      auto t0 = std::chrono::steady_clock::now();
      pt::Result<pt::Scene> s = pt::load_scene(f);
      double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (!s) {
        std::fprintf(stderr, "%s\n", s.error().c_str());
        return 2;
      }
      triangles = s->triangle_count();
      best = std::min(best, ms);
    }
    std::printf("%-40s %12zu %10.1f\n", f.c_str(), triangles, best);
  }
  return 0;
}
