// End-to-end throughput: spp/s and Mrays/s of the renderer on the built-in scenes (and the bunny when present),
// with 1 thread and all threads. Prints a table and writes CSV.
//   build/bench/bench_render_throughput [--size 512] [--seconds 5] [--csv out.csv] [--max-depth 8]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "render/renderer.h"
#include "scene/load.h"

using namespace pt;

namespace {

struct Row {
  std::string scene;
  int threads;
  double build_ms, spp_per_s, mrays_per_s;
  uint64_t triangles;
};

Row measure(const std::string& name, const Scene& scene, int threads, int size, double seconds, int max_depth,
            bool generic = false) {
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
  int frames = 0;
  while (elapsed < seconds || frames < 2) {
    renderer.render_frame(rs, params, film, uint32_t(frames++), counters);
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return {name, renderer.thread_count(), rs.trace().stats.build_ms, frames / elapsed, counters.rays() / elapsed * 1e-6,
          rs.triangle_count()};
}

}  // namespace

int main(int argc, char** argv) {
  int size = 512, max_depth = 8;
  double seconds = 5;
  std::string csv = "render_throughput.csv";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--size")) size = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--seconds")) seconds = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--csv")) csv = argv[i + 1];
    else if (!std::strcmp(argv[i], "--max-depth")) max_depth = std::atoi(argv[i + 1]);
  }
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
  std::printf("%-20s %8s %8s %10s %10s %10s\n", "scene", "tris", "threads", "build ms", "spp/s", "Mrays/s");
  std::ofstream out(csv);
  out << "scene,triangles,threads,build_ms,spp_per_s,mrays_per_s\n";
  for (auto& [name, scene] : scenes) {
    for (int t : {1, all}) {
      Row r = measure(name, scene, t, size, seconds, max_depth);
      std::printf("%-20s %8llu %8d %10.1f %10.2f %10.2f\n", r.scene.c_str(), (unsigned long long)r.triangles,
                  r.threads, r.build_ms, r.spp_per_s, r.mrays_per_s);
      out << r.scene << "," << r.triangles << "," << r.threads << "," << r.build_ms << "," << r.spp_per_s << ","
          << r.mrays_per_s << "\n";
      if (all == 1) break;
    }
  }
  // What the specialization on scene features buys: the diffuse-only box with the generic (all-materials) loop.
  for (auto& [name, scene] : scenes) {
    if (name != "cornell") continue;
    for (bool generic : {false, true}) {
      Row r = measure(name + (generic ? " generic" : " special"), scene, 1, size, seconds, max_depth, generic);
      std::printf("%-20s %8llu %8d %10.1f %10.2f %10.2f\n", r.scene.c_str(), (unsigned long long)r.triangles,
                  r.threads, r.build_ms, r.spp_per_s, r.mrays_per_s);
      out << r.scene << "," << r.triangles << "," << r.threads << "," << r.build_ms << "," << r.spp_per_s << ","
          << r.mrays_per_s << "\n";
    }
  }
  std::printf("wrote %s\n", csv.c_str());
}
