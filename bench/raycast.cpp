// Ray casting and BVH build against Embree 3: both trace the same ray sets on the same meshes.
//   build/bench/bench_raycast [--threads N] [--reps N] [--only cornell|bunny|knot|knot6m] [--csv out.csv]
//                             [--path-seconds S] [--clock wall|cpu] [--build-only 0|1]
// Meshes: the built-in Cornell box, ../shared/models/stanford-bunny.obj (when present), a ~1M-triangle torus knot;
// on request (--only knot6m) a 6.3M-triangle knot, the large-mesh report.
// each flattened by the renderer's own path (make_render_scene), so they are exactly the triangles it traces
// (the rectangle light included: the two triangles of its quad).
// Ray sets (generated once, deterministic, stored): primary rays (512x512, 4 jittered per pixel), diffuse bounces
// from our primary hits (closest hit), shadow rays from those hits to the rectangle light (any hit).
// Reported: Mrays/s with 1 and N threads, our/Embree ratio, disagreements on every ray; build time, Mtris/s, SAH
// cost against a full-sweep SAH build, bytes per triangle and peak memory against Embree's MEDIUM and HIGH builds;
// for the bunny, ptview's whole path loop (256x256, depth 8) in Mrays/s over Embree's diffuse-ray Mrays/s.
// Without Embree (not found by CMake) only our side runs and the Embree columns show "-".
#include <poll.h>
#include <time.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "accel/geometry.h"
#include "bench_cli.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "raycast_embree.h"
#include "render/camera.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "scene/load.h"
#include "scene/procedural.h"

using namespace pt;
using bench::EmbreeQuality;
using bench::EmbreeScene;

namespace {

constexpr int kImageSize = 512;
constexpr int kSamplesPerPixel = 4;
constexpr size_t kChunk = 4096;         // rays per work item of the thread pool
constexpr double kSweepTimeoutS = 20.0;  // the reference sweep build is abandoned after this
constexpr float kRelTolerance = 1e-4f;  // closest hits agree when |t_ours - t_embree| <= 1e-4 t_ours
constexpr int kListedPerSet = 3;        // disagreements printed in full (with a double-precision referee)

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// Thread CPU time (seconds) of the calling thread.
double thread_cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// --clock cpu: ray rates from the CPU time of the tracing threads (their mean) instead of the wall time, so that
/// time a thread spends descheduled on a loaded machine is not counted. Cache pollution by other processes still is.
bool g_cpu_clock = false;

/// The same simple pool for both tracers: `threads` std::threads take chunks of kChunk items from an atomic
/// counter and call fn(begin, end). Returns the wall time in seconds (thread start-up included: ~0.1 ms), or with
/// g_cpu_clock the mean CPU time of the threads.
template <class Fn>
double parallel_for(size_t n, int threads, Fn&& fn) {
  std::atomic<size_t> next{0};
  std::vector<double> cpu(size_t(threads), 0.0);
  auto worker = [&](int id) {
    const double start = thread_cpu_seconds();
    for (;;) {
      size_t begin = next.fetch_add(kChunk);
      if (begin >= n) break;
      fn(begin, std::min(n, begin + kChunk));
    }
    cpu[size_t(id)] = thread_cpu_seconds() - start;
  };
  auto start = Clock::now();
  std::vector<std::thread> pool;
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker, i);
  for (std::thread& t : pool) t.join();
  const double wall = ms_since(start) * 1e-3;
  if (!g_cpu_clock) return wall;
  double sum = 0.0;
  for (double c : cpu) sum += c;
  return sum / double(threads);
}

/// Runs fn in a fork()ed child and returns the numbers it produced, or nothing if it failed or did not finish
/// within timeout_s (then the child is killed). Gives the slow reference builder a time limit.
std::optional<std::vector<double>> run_in_child(const std::function<std::vector<double>()>& fn, double timeout_s) {
  int fds[2];
  if (pipe(fds) != 0) return std::nullopt;
  std::fflush(stdout);
  pid_t pid = fork();
  if (pid < 0) return std::nullopt;
  if (pid == 0) {
    close(fds[0]);
    std::vector<double> out = fn();
    ssize_t ignored = write(fds[1], out.data(), out.size() * sizeof(double));
    (void)ignored;
    _exit(0);
  }
  close(fds[1]);
  std::vector<double> result;
  bool done = false;
  auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    int left_ms = int(std::chrono::duration<double, std::milli>(deadline - Clock::now()).count());
    if (left_ms <= 0) break;
    pollfd p{fds[0], POLLIN, 0};
    if (poll(&p, 1, left_ms) <= 0) continue;
    double buf[16];
    ssize_t got = read(fds[0], buf, sizeof(buf));
    if (got <= 0) { done = true; break; }  // EOF: the child exited
    result.insert(result.end(), buf, buf + got / ssize_t(sizeof(double)));
  }
  close(fds[0]);
  if (!done) kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!done || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
  return result;
}

// ---------------------------------------------------------------------------------------------------------------
// Meshes

struct TestMesh {
  std::string name;
  RenderScene rs;  ///< flattened triangles (rs.geo->tri_vertices, origin-shifted), camera, lights
  std::optional<Light> light;  ///< the rectangle light the shadow rays aim at
  std::optional<Scene> path_scene;  ///< the scene as loaded (default camera), for the path-loop row (bunny)

  const std::vector<vec3>& vertices() const { return rs.geo->tri_vertices; }
  size_t triangles() const { return rs.triangle_count(); }
};

/// Flattens `scene` exactly as the renderer does. Bunny and knot are finalized scenes without camera or emitter,
/// so finalize_scene gave them framing_camera(bounds) (narrowed below) and a rectangle light above the bounds about
/// their size.
std::optional<TestMesh> make_test_mesh(const std::string& name, Scene scene) {
  TestMesh m;
  m.name = name;
  // framing_camera fits the bounding sphere, so most primary rays would miss; a narrower view fills the frame.
  if (name != "cornell" && scene.camera) scene.camera->fov_deg = 22.0f;
  m.rs = make_render_scene(scene);
  if (!m.rs.geo->spheres.empty())
    std::printf("%s: its %zu spheres are left out (Embree side has triangles only)\n", name.c_str(),
                m.rs.geo->spheres.size());
  for (const Light& l : m.rs.lights.lights)
    if (l.kind == LightKind::rect) {
      m.light = l;
      break;
    }
  if (!m.light) std::printf("%s: no rectangle light: no shadow rays\n", name.c_str());
  return m;
}

std::optional<TestMesh> load_test_mesh(const std::string& name) {
  if (name == "cornell") {
    Result<Scene> s = load_builtin_scene("cornell");
    if (!s) {
      std::printf("\ncornell: %s\n", s.error().c_str());
      return std::nullopt;
    }
    return make_test_mesh(name, *s);
  }
  if (name == "bunny") {
    std::filesystem::path path = std::filesystem::path(PTVIEW_SOURCE_DIR) / "../shared/models/stanford-bunny.obj";
    if (!std::filesystem::exists(path)) {
      std::printf("\nbunny: %s not found, skipped\n", path.c_str());
      return std::nullopt;
    }
    Result<Scene> s = load_scene(path.string());
    if (!s) {
      std::printf("\nbunny: %s\n", s.error().c_str());
      return std::nullopt;
    }
    std::optional<TestMesh> m = make_test_mesh(name, *s);
    if (m) m->path_scene = std::move(*s);
    return m;
  }
  if (name == "knot6m") {  // 2 * 8192 * 384 = 6,291,456 triangles: the large-mesh report (opt-in, --only knot6m)
    Scene scene;
    scene.source = "knot6m";
    scene.materials.push_back(Material{"knot"});
    TorusKnotParams params;
    params.segments = 8192;
    params.sides = 384;
    scene.meshes.push_back(make_torus_knot(params, 0));
    finalize_scene(scene);
    return make_test_mesh(name, scene);
  }
  // 2 * 4096 * 128 = 1,048,576 triangles (plus the light's two).
  Scene scene;
  scene.source = "knot";
  scene.materials.push_back(Material{"knot"});
  TorusKnotParams params;
  params.segments = 4096;
  params.sides = 128;
  scene.meshes.push_back(make_torus_knot(params, 0));
  finalize_scene(scene);
  return make_test_mesh(name, scene);
}

// ---------------------------------------------------------------------------------------------------------------
// Ray sets

struct RaySets {
  std::vector<Ray> primary, diffuse, shadow;
};

/// Primary rays through 4 jittered points per pixel; for each primary ray that hits (our closest hit), a
/// cosine-weighted bounce around the geometric normal on the incoming side and a shadow ray to a uniform point on
/// the light, both spawned the way the integrator spawns them (offset by the hit's error bound).
RaySets make_ray_sets(const TestMesh& m, const TraceGeometry& ours, int threads) {
  RaySets s;
  Pcg32 rng(0x5eedULL, 17);
  const CameraRig rig = make_camera_rig(m.rs.camera, kImageSize, kImageSize);
  s.primary.reserve(size_t(kImageSize) * kImageSize * kSamplesPerPixel);
  for (int j = 0; j < kImageSize; ++j)
    for (int i = 0; i < kImageSize; ++i)
      for (int k = 0; k < kSamplesPerPixel; ++k) {
        vec2 u(rng.next_float(), rng.next_float());
        s.primary.push_back(generate_camera_ray(rig, i, j, u));
      }
  std::vector<Hit> hits(s.primary.size());
  std::vector<uint8_t> hit(s.primary.size());
  parallel_for(s.primary.size(), threads, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      Ray r = s.primary[i];
      hit[i] = intersect_closest(ours, r, hits[i]);
    }
  });
  for (size_t i = 0; i < s.primary.size(); ++i) {
    vec2 u_bounce(rng.next_float(), rng.next_float()), u_light(rng.next_float(), rng.next_float());
    if (!hit[i]) continue;
    const Ray& r = s.primary[i];
    const SurfaceHit sh = make_surface_hit(m.rs, r, hits[i]);
    const vec3 n = glm::dot(sh.sp.ng, r.dir) > 0.0f ? -sh.sp.ng : sh.sp.ng;
    s.diffuse.push_back(spawn_ray(sh.sp, Frame::from_normal(n).to_world(sample_cosine_hemisphere(u_bounce))));
    // Area sampling: a uniform point on the rectangle. Points behind the light's plane get no ray (as in the
    // integrator): on the Cornell box that is the ceiling around the light.
    LightSample ls;
    if (m.light && sample_light(*m.light, sh.sp.p, u_light, LightSampling::area, ls))
      s.shadow.push_back(spawn_ray_to(sh.sp, ls.point));
  }
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// Output

struct Options {
  int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  int reps = 5;
  std::string csv = "raycast.csv";
  std::string only;
  double path_seconds = 3.0;
  bool build_only = false;  ///< --build-only 1: the build table only (no ray sets, no tracing)
};

std::string fmt(double v, const char* f = "%.2f") {
  if (v < 0.0 || !std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

/// One CSV for both tables: the columns a row does not have stay empty.
struct Csv {
  std::ofstream out;
  explicit Csv(const std::string& path) : out(path) {
    out << "table,mesh,triangles,name,threads,rays,hits,ours_mrays_per_s,embree_mrays_per_s,ours_over_embree,"
           "hit_miss_disagreements,t_disagreements,build_ms,mtris_per_s,sah_cost,sah_cost_sweep,sah_over_sweep,"
           "bytes_per_triangle,peak_rss_mb,embree_monitor_peak_mb,first_build_ms\n";
  }
  static std::string cell(double v) {
    if (v < 0.0 || !std::isfinite(v)) return "";
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.6g", v);
    return buf;
  }
  void row(std::initializer_list<std::string> cells) {
    bool first = true;
    for (const std::string& c : cells) out << (first ? "" : ",") << c, first = false;
    out << "\n";
  }
};

// ---------------------------------------------------------------------------------------------------------------
// Build table

struct BuildRow {
  std::string builder;
  int threads = 1;
  double ms = -1, first_ms = -1, sah = -1, sah_sweep = -1, bytes_per_tri = -1, peak_rss = -1, monitor_peak = -1;
};

void print_build_header() {
  std::printf("%-8s %9s  %-15s %7s %10s %9s %8s %7s %9s %9s %9s %9s %9s\n", "mesh", "tris", "builder", "threads", "ms",
              "1st ms", "Mtris/s", "SAH", "SAH swp", "SAH/swp", "B/tri", "peak MB", "mon. MB");
}

void emit_build_row(const TestMesh& m, const BuildRow& r, Csv& csv) {
  const double tris = double(m.triangles());
  const double mtris = r.ms > 0.0 ? tris / (r.ms * 1e3) : -1.0;
  const double ratio = r.sah > 0.0 && r.sah_sweep > 0.0 ? r.sah / r.sah_sweep : -1.0;
  const char* ms_format = r.ms < 1.0 ? "%.3f" : r.ms < 100.0 ? "%.2f" : "%.1f";
  std::printf("%-8s %9zu  %-15s %7d %10s %9s %8s %7s %9s %9s %9s %9s %9s\n", m.name.c_str(), m.triangles(),
              r.builder.c_str(), r.threads, fmt(r.ms, ms_format).c_str(), fmt(r.first_ms, ms_format).c_str(),
              fmt(mtris).c_str(), fmt(r.sah).c_str(),
              fmt(r.sah_sweep).c_str(), fmt(ratio, "%.3f").c_str(), fmt(r.bytes_per_tri, "%.1f").c_str(),
              fmt(r.peak_rss * 1e-6, "%.1f").c_str(), fmt(r.monitor_peak * 1e-6, "%.1f").c_str());
  csv.row({"build", m.name, std::to_string(m.triangles()), r.builder, std::to_string(r.threads), "", "", "", "", "",
           "", "", Csv::cell(r.ms), Csv::cell(mtris), Csv::cell(r.sah), Csv::cell(r.sah_sweep), Csv::cell(ratio),
           Csv::cell(r.bytes_per_tri), Csv::cell(r.peak_rss * 1e-6), Csv::cell(r.monitor_peak * 1e-6),
           Csv::cell(r.first_ms)});
}

/// Our build with `threads` threads, `reps` times; returns the last geometry. Peak memory: growth of the process's
/// peak RSS during the build (PeakRssProbe; the previous tree is freed first), the largest over the repetitions.
/// The first repetition starts with the huge-block cache emptied (core/huge_page_allocator.h), so first_ms is a
/// cold build whose memory comes fresh from the kernel; the later ones reuse the blocks, as a viewer's rebuilds do.
TraceGeometry build_ours(const TestMesh& m, int threads, int reps, BuildRow& row) {
  BvhBuildOptions options;
  options.threads = threads;
  std::vector<double> ms;
  TraceGeometry g;
  for (int r = 0; r < reps; ++r) {
    g = TraceGeometry{};
    if (r == 0) huge_block_cache::release_all();
    bench::PeakRssProbe probe;
    auto start = Clock::now();
    g = make_trace_geometry(m.vertices(), {}, options);
    ms.push_back(ms_since(start));
    row.peak_rss = std::max(row.peak_rss, probe.growth());
  }
  row.builder = "ours";
  row.threads = threads;
  row.ms = median(ms);
  row.first_ms = ms.front();
  row.sah = g.stats.sah_cost;
  row.bytes_per_tri = double(g.stats.memory_bytes) / double(m.triangles());
  return g;
}

/// The full-sweep SAH reference over the same triangle boxes and centers make_trace_geometry uses, in a child
/// process with a time limit. Returns {ms, sah} or nothing.
std::optional<std::vector<double>> build_sweep(const TestMesh& m) {
  return run_in_child(
      [&] {
        const std::vector<vec3>& v = m.vertices();
        std::vector<AABB> boxes(m.triangles());
        std::vector<vec3> centers(m.triangles());
        for (size_t i = 0; i < boxes.size(); ++i) {
          for (int k = 0; k < 3; ++k) boxes[i].extend(v[3 * i + k]);
          centers[i] = boxes[i].center();
        }
        // The options make_trace_geometry builds its binary triangle tree with.
        const BvhBuildOptions options = triangle_build_options({});
        auto start = Clock::now();
        Bvh bvh = build_bvh_sweep(boxes, centers, options);
        double ms = ms_since(start);
        return std::vector<double>{ms, double(sah_cost(bvh, options.traversal_cost))};
      },
      kSweepTimeoutS);
}

/// Embree's build at `quality` with `threads` (0 = Embree's default), `reps` times; returns the last scene.
std::unique_ptr<EmbreeScene> build_embree(const TestMesh& m, EmbreeQuality quality, int threads, int shown_threads,
                                          int reps, BuildRow& row) {
  std::vector<double> ms;
  std::unique_ptr<EmbreeScene> scene;
  for (int r = 0; r < reps; ++r) {
    scene.reset();
    scene = std::make_unique<EmbreeScene>(m.vertices(), quality, threads);
    ms.push_back(scene->build().ms);
    row.peak_rss = std::max(row.peak_rss, scene->build().rss_peak);
    row.monitor_peak = std::max(row.monitor_peak, scene->build().monitor_peak);
  }
  row.builder = quality == EmbreeQuality::high ? "Embree high" : "Embree medium";
  row.threads = shown_threads;
  row.ms = median(ms);
  row.first_ms = ms.front();
  row.bytes_per_tri = scene->build().net_bytes / double(m.triangles());
  return scene;
}

// ---------------------------------------------------------------------------------------------------------------
// Trace table

struct ClosestResult {
  float t = kInfinity;  ///< kInfinity on a miss
  uint32_t prim = ~0u;
};

struct TraceRow {
  std::string set;
  int threads = 1;
  size_t rays = 0, hits = 0;
  double ours = -1, embree = -1;  // Mrays/s
  long long hit_miss = -1, t_diff = -1;
};

void print_trace_header() {
  std::printf("%-8s %-8s %8s %9s %9s  %12s %12s %11s %10s %10s\n", "mesh", "set", "threads", "rays", "hit %",
              "ours Mray/s", "Embree Mr/s", "ours/Embree", "hit/miss", "t diff");
}

void emit_trace_row(const TestMesh& m, const TraceRow& r, Csv& csv) {
  const double ratio = r.ours > 0.0 && r.embree > 0.0 ? r.ours / r.embree : -1.0;
  std::printf("%-8s %-8s %8d %9zu %9s  %12s %12s %11s %10s %10s\n", m.name.c_str(), r.set.c_str(), r.threads, r.rays,
              fmt(100.0 * double(r.hits) / double(std::max<size_t>(1, r.rays)), "%.1f").c_str(), fmt(r.ours).c_str(),
              fmt(r.embree).c_str(), fmt(ratio, "%.3f").c_str(), fmt(double(r.hit_miss), "%.0f").c_str(),
              fmt(double(r.t_diff), "%.0f").c_str());
  csv.row({"trace", m.name, std::to_string(m.triangles()), r.set, std::to_string(r.threads), std::to_string(r.rays),
           std::to_string(r.hits), Csv::cell(r.ours), Csv::cell(r.embree), Csv::cell(ratio),
           r.hit_miss < 0 ? "" : std::to_string(r.hit_miss), r.t_diff < 0 ? "" : std::to_string(r.t_diff), "", "", "",
           "", "", "", "", ""});
}

/// Moller-Trumbore in double precision against triangle `tri` (both sides): sets t and the smallest of the three
/// barycentrics (negative: outside, by that much; near 0: the ray passes an edge).
void double_precision_test(const std::vector<vec3>& v, size_t tri, const Ray& r, double& t, double& b_min) {
  using d3 = glm::dvec3;
  const d3 o(r.org), d(r.dir), p0(v[3 * tri]), e1 = d3(v[3 * tri + 1]) - p0, e2 = d3(v[3 * tri + 2]) - p0;
  const d3 q = glm::cross(d, e2), s = o - p0, w = glm::cross(s, e1);
  const double det = glm::dot(e1, q);
  const double b1 = glm::dot(s, q) / det, b2 = glm::dot(d, w) / det;
  t = glm::dot(e2, w) / det;
  b_min = det == 0.0 ? -kInfinity : std::min({b1, b2, 1.0 - b1 - b2});
}

/// The referee for listed disagreements: the closest hit in (0, tmax) over every triangle, in double precision.
/// Returns {t, prim}, t = inf and prim -1 on a miss.
std::pair<double, int> brute_force_closest(const std::vector<vec3>& v, const Ray& r) {
  std::pair<double, int> best{double(kInfinity), -1};
  for (size_t i = 0; i < v.size() / 3; ++i) {
    double t, b_min;
    double_precision_test(v, i, r, t, b_min);
    if (b_min >= 0.0 && t > 0.0 && t < double(r.tmax) && t < best.first) best = {t, int(i)};
  }
  return best;
}

/// "prim 7 (b_min -1.2e-09)": a hit triangle with its smallest double-precision barycentric for the ray.
std::string describe_prim(const std::vector<vec3>& v, uint32_t prim, const Ray& r) {
  if (prim == ~0u) return "-";
  double t, b_min;
  double_precision_test(v, prim, r, t, b_min);
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%u (b_min %.2g)", prim, b_min);
  return buf;
}

std::string describe(const Ray& r) {
  char buf[160];
  std::snprintf(buf, sizeof(buf), "org (%.9g, %.9g, %.9g) dir (%.9g, %.9g, %.9g) tmax %.9g", r.org.x, r.org.y,
                r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmax);
  return buf;
}

/// Median seconds over `reps` runs of fn over the rays, in Mrays/s.
template <class Fn>
double mrays_per_s(size_t n, int threads, int reps, Fn&& fn) {
  std::vector<double> secs;
  for (int r = 0; r < reps; ++r) secs.push_back(parallel_for(n, threads, fn));
  return double(n) / median(secs) * 1e-6;
}

/// Closest-hit set: time both tracers, then compare every ray's result (notes: the first few disagreements).
TraceRow trace_closest(const std::string& set, const std::vector<Ray>& rays, const TestMesh& m,
                       const TraceGeometry& ours, const EmbreeScene* embree, int threads, int reps,
                       std::vector<std::string>* notes) {
  std::vector<ClosestResult> a(rays.size()), b(rays.size());
  TraceRow row{set, threads, rays.size()};
  row.ours = mrays_per_s(rays.size(), threads, reps, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      Ray r = rays[i];
      Hit h;
      a[i] = intersect_closest(ours, r, h) ? ClosestResult{h.t, h.prim} : ClosestResult{};
    }
  });
  for (const ClosestResult& x : a) row.hits += x.t < kInfinity;
  if (!embree) return row;
  row.embree = mrays_per_s(rays.size(), threads, reps, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      ClosestResult x;
      b[i] = embree->intersect(rays[i], x.t, x.prim) ? x : ClosestResult{};
    }
  });
  row.hit_miss = row.t_diff = 0;
  int listed = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const bool ha = a[i].t < kInfinity, hb = b[i].t < kInfinity;
    bool bad = false;
    if (ha != hb) bad = true, ++row.hit_miss;
    else if (ha && std::abs(a[i].t - b[i].t) > kRelTolerance * a[i].t) bad = true, ++row.t_diff;
    if (bad && notes && listed++ < kListedPerSet) {
      const auto [ref_t, ref_prim] = brute_force_closest(m.vertices(), rays[i]);
      char buf[300];
      std::snprintf(buf, sizeof(buf), ": ours t %.9g prim %s, Embree t %.9g prim %s, double precision t %.9g prim %s",
                    a[i].t, describe_prim(m.vertices(), a[i].prim, rays[i]).c_str(), b[i].t,
                    describe_prim(m.vertices(), b[i].prim, rays[i]).c_str(), ref_t,
                    describe_prim(m.vertices(), uint32_t(ref_prim), rays[i]).c_str());
      notes->push_back(set + " ray " + std::to_string(i) + ": " + describe(rays[i]) + buf);
    }
  }
  return row;
}

/// Any-hit set (shadow rays): same, comparing the occluded flags.
TraceRow trace_any(const std::string& set, const std::vector<Ray>& rays, const TestMesh& m,
                   const TraceGeometry& ours, const EmbreeScene* embree, int threads, int reps,
                   std::vector<std::string>* notes) {
  std::vector<uint8_t> a(rays.size()), b(rays.size());
  TraceRow row{set, threads, rays.size()};
  row.ours = mrays_per_s(rays.size(), threads, reps, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) a[i] = intersect_any(ours, rays[i]);
  });
  for (uint8_t x : a) row.hits += x;
  if (!embree) return row;
  row.embree = mrays_per_s(rays.size(), threads, reps, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) b[i] = embree->occluded(rays[i]);
  });
  row.hit_miss = 0;
  int listed = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (a[i] == b[i]) continue;
    ++row.hit_miss;
    if (notes && listed++ < kListedPerSet) {
      const bool ref = brute_force_closest(m.vertices(), rays[i]).second >= 0;
      notes->push_back(set + " ray " + std::to_string(i) + ": " + describe(rays[i]) + ": ours " +
                       (a[i] ? "occluded" : "clear") + ", Embree " + (b[i] ? "occluded" : "clear") +
                       ", double precision " + (ref ? "occluded" : "clear"));
    }
  }
  return row;
}

/// ptview's path loop: 256x256, max depth 8, default integrator, light sampling and sampler, 1-spp frames for at
/// least `seconds` (and 2 passes), `frames_per_pass` of them in each pass over the tiles
/// (ProgressiveFilm::frames_per_pass: the headless mode renders up to 16 per pass, 16 on this scene; the viewer
/// about 1/30 s of frames, 2-4 here). Mrays/s counts camera, bounce and shadow rays.
struct PathLoopResult {
  double spp_per_s = -1, mrays_per_s = -1;
};
PathLoopResult run_path_loop(const RenderScene& rs, int threads, double seconds, int frames_per_pass) {
  RenderParams params;
  params.width = params.height = 256;
  params.max_depth = 8;
  params.threads = threads;
  params.spp_per_frame = frames_per_pass;
  Renderer renderer(threads);
  Film film(params.width, params.height);
  RenderCounters counters;
  auto process_cpu = [] {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  };
  const auto start = Clock::now();
  const double cpu_start = process_cpu();
  double elapsed = 0.0;
  int passes = 0;
  while (elapsed < seconds || passes < 2) {
    renderer.render_frame(rs, params, film, uint32_t(passes++), counters);
    elapsed = ms_since(start) * 1e-3;
  }
  // --clock cpu: the process's CPU time over the threads (the pool's threads sleep between frames).
  if (g_cpu_clock) elapsed = (process_cpu() - cpu_start) / double(renderer.thread_count());
  return {double(passes) * frames_per_pass / elapsed, double(counters.rays()) / elapsed * 1e-6};
}

// ---------------------------------------------------------------------------------------------------------------

void run_mesh(const TestMesh& m, const Options& opt, Csv& csv) {
  const bool have_embree = bench::embree_available();
  const int hw = int(std::max(1u, std::thread::hardware_concurrency()));
  const std::vector<int> thread_counts = opt.threads == 1 ? std::vector<int>{1} : std::vector<int>{1, opt.threads};

  // Build table. Ours first (the last all-threads tree is the one traced), then the sweep reference, then Embree.
  std::printf("\n");
  print_build_header();
  TraceGeometry ours;
  BuildRow ours_rows[2];
  for (size_t k = 0; k < thread_counts.size(); ++k) ours = build_ours(m, thread_counts[k], opt.reps, ours_rows[k]);
  std::optional<std::vector<double>> sweep = build_sweep(m);
  for (size_t k = 0; k < thread_counts.size(); ++k) {
    if (sweep && sweep->size() == 2) ours_rows[k].sah_sweep = (*sweep)[1];
    emit_build_row(m, ours_rows[k], csv);
  }
  if (sweep && sweep->size() == 2) {
    BuildRow r;
    r.builder = "sweep SAH (ref)";
    r.ms = (*sweep)[0];
    r.sah = r.sah_sweep = (*sweep)[1];
    emit_build_row(m, r, csv);
  } else {
    std::printf("%-8s %9zu  sweep SAH (ref): did not finish within %.0f s, skipped\n", m.name.c_str(),
                m.triangles(), kSweepTimeoutS);
  }
  std::unique_ptr<EmbreeScene> embree;  // traced: MEDIUM quality, default threads (Embree's default build)
  if (have_embree) {
    for (EmbreeQuality q : {EmbreeQuality::medium, EmbreeQuality::high})
      for (int t : thread_counts) {
        BuildRow r;
        // "threads=N" only when N is not already Embree's default (all hardware threads).
        auto scene = build_embree(m, q, t == hw && t != 1 ? 0 : t, t, opt.reps, r);
        emit_build_row(m, r, csv);
        if (q == EmbreeQuality::medium && t == thread_counts.back()) embree = std::move(scene);
      }
  }

  if (opt.build_only) return;
  // Trace table.
  const RaySets sets = make_ray_sets(m, ours, opt.threads);
  std::printf("\n");
  print_trace_header();
  std::vector<std::string> notes;
  std::vector<double> embree_diffuse;  // per entry of thread_counts, for the path-loop ratio
  for (int t : thread_counts) {
    std::vector<std::string>* n = t == 1 ? &notes : nullptr;  // disagreements are listed once (1-thread rows)
    emit_trace_row(m, trace_closest("primary", sets.primary, m, ours, embree.get(), t, opt.reps, n), csv);
    const TraceRow diffuse = trace_closest("diffuse", sets.diffuse, m, ours, embree.get(), t, opt.reps, n);
    emit_trace_row(m, diffuse, csv);
    embree_diffuse.push_back(diffuse.embree);
    if (!sets.shadow.empty())
      emit_trace_row(m, trace_any("shadow", sets.shadow, m, ours, embree.get(), t, opt.reps, n), csv);
  }
  for (const std::string& s : notes) std::printf("  disagreement: %s\n", s.c_str());
  if (!m.path_scene) return;
  // The whole path loop against bare rays: ptview's own Mrays/s (camera + bounce + shadow rays, as mrays_per_s in
  // the stats JSON) rendering the scene as loaded, over Embree's diffuse-ray Mrays/s measured above in this run.
  // Two loops: a pass per 1-spp frame (the viewer's when a frame takes 1/30 s or more) and the headless mode's 16.
  std::printf("\n%-8s %-36s %8s %12s %16s %11s\n", "mesh", "path loop (256x256, depth 8, defaults)", "threads",
              "spp/s", "ptview Mrays/s", "/ Embree diffuse");
  const RenderScene rs = make_render_scene(*m.path_scene);
  for (size_t k = 0; k < thread_counts.size(); ++k)
    for (auto [loop, frames_per_pass] : {std::pair{"1 frame per pass", 1}, {"16 frames per pass (headless)", 16}}) {
      const PathLoopResult p = run_path_loop(rs, thread_counts[k], opt.path_seconds, frames_per_pass);
      const double ratio = embree_diffuse[k] > 0.0 ? p.mrays_per_s / embree_diffuse[k] : -1.0;
      std::printf("%-8s %-36s %8d %12s %16s %11s\n", m.name.c_str(), loop, thread_counts[k], fmt(p.spp_per_s).c_str(),
                  fmt(p.mrays_per_s).c_str(), fmt(ratio, "%.3f").c_str());
      const std::string set = "path loop 256x256 depth 8 " + std::to_string(frames_per_pass) + " frames per pass";
      csv.row({"path", m.name, std::to_string(m.triangles()), set, std::to_string(thread_counts[k]), "", "",
               Csv::cell(p.mrays_per_s), Csv::cell(embree_diffuse[k]), Csv::cell(ratio), "", "", "", "", "", "", "",
               "", "", ""});
    }
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  std::string clock = "wall";
  CLI::App app{"Our BVH against Embree 3 on the same primary, diffuse and shadow rays: throughput, agreement of every "
               "hit, build time, SAH, memory, and the bunny path loop against Embree's diffuse rays.",
               "bench_raycast"};
  app.add_option("--threads", opt.threads, "Also measure at N threads (default: all cores)")->check(CLI::Range(1, 1024));
  app.add_option("--reps", opt.reps, "Runs per measurement, median reported (default 5)")->check(CLI::Range(1, 1000));
  app.add_option("--csv", opt.csv, "CSV output");
  app.add_option("--only", opt.only, "One mesh")->check(CLI::IsMember({"cornell", "bunny", "knot", "knot6m"}));
  app.add_option("--clock", clock, "wall (default) or cpu: rays per second of the tracing threads' CPU time")
      ->check(CLI::IsMember({"wall", "cpu"}));
  app.add_option("--build-only", opt.build_only, "1: the build table only");
  app.add_option("--path-seconds", opt.path_seconds, "Seconds of each path-loop run (0: none)")
      ->check(CLI::Range(0.0, 3600.0));
  if (std::optional<int> exit_code = bench::parse_command_line(app, argc, argv)) return *exit_code;
  g_cpu_clock = clock == "cpu";
  std::printf("bench_raycast: %dx%d x %d primary rays; threads 1%s; times: median of %d runs\n", kImageSize,
              kImageSize, kSamplesPerPixel, opt.threads > 1 ? (" and " + std::to_string(opt.threads)).c_str() : "",
              opt.reps);
  if (bench::embree_available())
    std::printf("Embree %s: traced with its default build (MEDIUM, all threads), rtcIntersect1 / rtcOccluded1\n",
                bench::embree_version().c_str());
  else
    std::printf("Embree 3 was not found when configuring: our side only\n");
  if (g_cpu_clock) std::printf("ray rates: rays per second of CPU time of the tracing threads (--clock cpu)\n");
  std::printf("disagreements: hit/miss = one hits and the other misses (shadow: occluded flags differ); "
              "t diff = both hit, |t_ours - t_embree| > 1e-4 t\n");
  std::printf("peak MB: growth of the process's peak RSS during the build; mon. MB: Embree's memory monitor; "
              "B/tri: ours stats.memory_bytes, Embree net bytes after the commit\n");
  Csv csv(opt.csv);
  for (const char* name : {"cornell", "bunny", "knot", "knot6m"}) {
    // knot6m (6.3M triangles, the large-mesh report) runs only when asked for.
    if (opt.only.empty() ? std::strcmp(name, "knot6m") == 0 : opt.only != name) continue;
    std::optional<TestMesh> m = load_test_mesh(name);
    if (m) run_mesh(*m, opt, csv);
  }
  std::printf("\nwrote %s\n", opt.csv.c_str());
}
