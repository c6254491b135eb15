// End-to-end throughput: spp/s and Mrays/s of the renderer on the built-in scenes (and the bunny when present),
// with 1 thread and all threads, rendering frames in passes as `ptview --frames N` does (the largest pass is
// reported). Prints a table and writes CSV.
//   build/bench/bench_render_throughput [--size 512] [--seconds 5] [--csv out.csv] [--max-depth 8]
//                                       [--max-frames-per-pass 16]   (1: a frame per pass, as before round 13)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_cli.h"
#include "render/adaptive.h"
#include "render/renderer.h"
#include "scene/load.h"

using namespace pt;

namespace {

struct Row {
  std::string scene;
  int threads;
  double build_ms, spp_per_s, mrays_per_s;
  uint64_t triangles;
  int frames_per_pass;
};

Row measure(const std::string& name, const Scene& scene, int threads, int size, double seconds, int max_depth,
            int max_frames_per_pass, bool generic = false) {
  RenderScene rs = make_render_scene(scene);
  RenderParams params;
  params.width = params.height = size;
  params.max_depth = max_depth;
  params.threads = threads;
  params.force_generic_kernel = generic;
  Renderer renderer(threads);
  Film film(size, size);
  RenderCounters counters;
  auto start = std::chrono::steady_clock::now();
  double elapsed = 0;
  int frames = 0, max_pass = 1;
  while (elapsed < seconds || frames < 2) {
    // Passes of several frames, as `ptview --frames N` renders them (app/headless.cpp): about kHeadlessPassSeconds
    // at the measured time per frame; the first pass is one frame, to measure it. As there, a pass is one frame of
    // `pass` samples a pixel, continuing from each pixel's next sample index.
    const int pass = std::min(frames_for_pass_time(frames > 0 ? elapsed / frames : 0.0, kHeadlessPassSeconds),
                              max_frames_per_pass);
    RenderParams p = params;
    p.spp_per_frame = pass * params.spp_per_frame;
    renderer.render_pass(rs, p, film, nullptr, counters);
    frames += pass;
    max_pass = std::max(max_pass, pass);
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const double spp_per_s = frames / elapsed, mrays_per_s = counters.rays() / elapsed * 1e-6;
  return {name, renderer.thread_count(), rs.trace().stats.build_ms, spp_per_s, mrays_per_s, rs.triangle_count(),
          max_pass};
}

void print_row(const Row& r, std::ofstream& out) {
  std::printf("%-20s %8llu %8d %10.1f %10.2f %10.2f %12d\n", r.scene.c_str(), (unsigned long long)r.triangles,
              r.threads, r.build_ms, r.spp_per_s, r.mrays_per_s, r.frames_per_pass);
  out << r.scene << "," << r.triangles << "," << r.threads << "," << r.build_ms << "," << r.spp_per_s << ","
      << r.mrays_per_s << "," << r.frames_per_pass << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  int size = 512, max_depth = 8, max_frames_per_pass = kMaxFramesPerPass;
  double seconds = 5;
  std::string csv = "render_throughput.csv";
  CLI::App app{"spp/s and Mrays/s of the renderer on the built-in scenes (and the bunny when present), 1 thread "
               "and all threads, frames in passes as `ptview --frames N` renders them.",
               "bench_render_throughput"};
  app.add_option("--size", size, "Image width and height (default 512)")->check(CLI::Range(1, 8192));
  app.add_option("--seconds", seconds, "Seconds per scene and thread count (default 5)")->check(CLI::Range(0.01, 3600.0));
  app.add_option("--csv", csv, "CSV output (default render_throughput.csv)");
  app.add_option("--max-depth", max_depth, "Maximum path depth (default 8)")->check(CLI::Range(1, 1 << 16));
  app.add_option("--max-frames-per-pass", max_frames_per_pass, "Frames rendered as one pass (default 16)")
      ->check(CLI::Range(1, 1 << 16));
  if (std::optional<int> exit_code = bench::parse_command_line(app, argc, argv)) return *exit_code;
  std::vector<std::pair<std::string, Scene>> scenes;
  for (const char* name : {"cornell", "cornell-glass", "cornell-mirror", "cornell-spheres", "cornell-large-mesh"}) {
    Result<Scene> s = load_builtin_scene(name);
    if (s) scenes.emplace_back(name, std::move(*s));
  }
  std::filesystem::path bunny = std::filesystem::path(PTVIEW_SOURCE_DIR) / "../shared/models/stanford-bunny.obj";
  if (std::filesystem::exists(bunny)) {
    Result<Scene> s = load_scene(bunny.string());
    if (s) scenes.emplace_back("bunny", std::move(*s));
  }
  int all = int(std::max(1u, std::thread::hardware_concurrency()));
  std::printf("%-20s %8s %8s %10s %10s %10s %12s\n", "scene", "tris", "threads", "build ms", "spp/s", "Mrays/s",
              "frames/pass");
  std::ofstream out(csv);
  out << "scene,triangles,threads,build_ms,spp_per_s,mrays_per_s,frames_per_pass\n";
  for (auto& [name, scene] : scenes) {
    for (int t : {1, all}) {
      Row r = measure(name, scene, t, size, seconds, max_depth, max_frames_per_pass);
      print_row(r, out);
      if (all == 1) break;
    }
  }
  // What the specialization on scene features buys: the diffuse-only box with the generic (all-materials) loop.
  for (auto& [name, scene] : scenes) {
    if (name != "cornell") continue;
    for (bool generic : {false, true}) {
      Row r = measure(name + (generic ? " generic" : " special"), scene, 1, size, seconds, max_depth,
                      max_frames_per_pass, generic);
      print_row(r, out);
    }
  }
  std::printf("wrote %s\n", csv.c_str());
}
