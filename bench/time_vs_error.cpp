// Error against wall time for each sampling strategy and sampler (issue: run time against error).
// For every scene: a reference (analytic where known, else a high-spp render cached outside the repo, rendered as
// two halves A and B with different seeds), then progressive renders recording (spp, seconds, rmse, rel_mse) after
// each power-of-two spp count. With a rendered reference, rel_mse is corrected for the reference's own noise: the
// measured mean of (x - r)^2 / (r^2 + 0.01) is E[(x - truth)^2] + Var(r) (per pixel), and (A - B)^2 / 4 estimates
// Var(r) without bias, so its weighted mean is subtracted (the raw value is the rel_mse_raw column).
// Efficiency = 1 / (rel_mse x seconds). Strategy "defaults" is what ptview runs with no strategy flags.
//   build/bench/bench_time_vs_error [--size 128] [--max-spp 256] [--ref-spp 4096] [--cache DIR] [--csv FILE]
//                                   [--scenes a,b,...] [--max-depth 64] [--threads 0] [--clock wall|cpu]
//                                   [--strategies defaults,bsdf,...] [--seed 0] [--sampler-cost FRAMES]
//                                   [--repeat N] [--max-frames-per-pass 16]
// Frames are rendered in passes of several, as `ptview --frames N` renders them (--max-frames-per-pass 1: one frame
// a pass, the viewer's loop on a large window); the films are the same either way.
// After the table: issue 11's targets 2 and 3 (print_targets); --repeat N renders every pair N times (seeds apart)
// and compares medians there, the table and CSV keeping the first run.
// --sampler-cost FRAMES: only Sobol's frame time against independent's, frames rendered alternately (see
// sampler_cost), for the scenes of --scenes with --size and --max-depth.
// --clock cpu counts process CPU seconds divided by the thread count instead of wall seconds: a proxy for a quiet
// machine's wall time when other work shares the cores (for tuning; published figures use wall time).
// Scene cornell36 (only when named in --scenes): bench/data/cornell36.obj with its ceiling light emitting
// (17, 12, 4), no background (the issue-11 set-up: 256x256, --max-depth 8, --threads 2, see `make bench-cornell36`).
// Then: python3 bench/plot_time_vs_error.py FILE.csv docs/img
// Convergence sections (issue 12; --convergence estimator|adaptive|both|only|none, default both): est_rel_mse
// against rel_mse on 32x32 renders (--conv-size, --conv-ref-spp 4096, --conv-seeds 8: the mean over that many
// seeds), then adaptive against uniform sampling at equal time on the glass box (honours --clock). Both subtract
// the rendered references' own noise as above; the plane's reference is its closed form.
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "app/app.h"
#include "bench_cli.h"
#include "render/camera.h"
#include "render/analytic.h"
#include "render/adaptive.h"
#include "render/convergence.h"
#include "render/image_error.h"
#include "render/renderer.h"
#include "scene/load.h"

using namespace pt;
namespace fs = std::filesystem;

namespace {

struct Strategy {
  const char* name;
  IntegratorKind integrator;
  LightSampling light_sampling;
};
const Strategy kStrategies[] = {
    {"defaults", RenderParams{}.integrator, RenderParams{}.light_sampling},
    {"assignment(nee+area)", IntegratorKind::nee, LightSampling::area},
    {"nee+solid-angle", IntegratorKind::nee, LightSampling::solid_angle},
    {"mis+solid-angle", IntegratorKind::mis, LightSampling::solid_angle},
    {"bsdf", IntegratorKind::bsdf, LightSampling::solid_angle},
};
const std::pair<const char*, SamplerKind> kSamplers[] = {{"independent", SamplerKind::independent},
                                                         {"sobol", SamplerKind::sobol}};

/// A small very bright light in the Cornell box: where uniform area sampling of a big light is not the issue but
/// BSDF sampling struggles.
Scene make_small_light_scene() {
  Result<Scene> s = load_builtin_scene("cornell");
  Scene scene = std::move(*s);
  for (Quad& q : scene.quads) {
    if (!scene.materials[q.material].emissive()) continue;
    vec3 c = q.corner + 0.5f * (q.edge1 + q.edge2);
    q.edge1 *= 0.1f;
    q.edge2 *= 0.1f;
    q.corner = c - 0.5f * (q.edge1 + q.edge2);
    scene.materials[q.material].emission *= 100.0f;
  }
  scene.source = "small-bright-light";
  return scene;
}

/// Uniform background 1 and albedo-1 objects: the exact image is 1 everywhere.
Scene make_furnace_scene() {
  Scene s;
  s.source = "furnace";
  s.background = vec3(1.0f);
  Material white;
  white.albedo = vec3(1.0f);
  s.materials.push_back(white);
  Material glass;
  glass.type = MaterialType::glass;
  s.materials.push_back(glass);
  s.spheres.push_back({vec3(-0.6f, 0, 0), 0.5f, 0});
  s.spheres.push_back({vec3(0.6f, 0, 0), 0.5f, 1});
  s.camera = Camera{vec3(0, 0, 4), vec3(0.0f), vec3(0, 1, 0), 40.0f};
  return s;
}

/// A diffuse plane under a rectangle light (the light has zero albedo, the background is black): every path that
/// leaves the plane either hits the light or escapes, so the exact image is (albedo / pi) E(x) on the plane, with
/// E from Lambert's polygon formula, and the light's radiance where it is seen.
struct PlaneScene {
  Scene scene;
  std::vector<dvec3> light;  ///< light polygon
  double albedo = 0.7, radiance = 5.0;
};

PlaneScene make_plane_scene() {
  PlaneScene ps;
  Scene& s = ps.scene;
  s.source = "rect-light-over-plane";
  Material floor;
  floor.albedo = vec3(float(ps.albedo));
  s.materials.push_back(floor);
  Material light;
  light.albedo = vec3(0.0f);
  light.emission = vec3(float(ps.radiance));
  s.materials.push_back(light);
  s.quads.push_back({vec3(-20, 0, 20), vec3(40, 0, 0), vec3(0, 0, -40), 0});
  vec3 c(-0.4f, 0.8f, -0.3f), e1(0.8f, 0, 0), e2(0, 0, 0.6f);  // faces down
  s.quads.push_back({c, e1, e2, 1});
  ps.light = {dvec3(c), dvec3(c + e1), dvec3(c + e1 + e2), dvec3(c + e2)};
  s.camera = Camera{vec3(0, 2.5f, 3.0f), vec3(0, 0, 0), vec3(0, 1, 0), 45.0f};
  return ps;
}


/// The exact radiance along one camera ray of the plane scene, or 0 where the ray sees black.
double exact_plane_radiance(const PlaneScene& ps, const Ray& r) {
  dvec3 o(r.org), d(r.dir);
  // The light (plane y = 0.8, seen from above: its back, black) hides the floor behind it.
  double tl = (0.8 - o.y) / d.y;
  dvec3 pl = o + tl * d;
  if (tl > 0 && pl.x > -0.4 && pl.x < 0.4 && pl.z > -0.3 && pl.z < 0.3) return 0.0;
  double t = -o.y / d.y;
  if (!(t > 0)) return 0.0;
  dvec3 p = o + t * d;
  if (std::abs(p.x) > 20 || std::abs(p.z) > 20) return 0.0;
  return ps.albedo / M_PI * polygon_irradiance(ps.light, p, dvec3(0, 1, 0), ps.radiance);
}

/// The exact image, box-filtered: the closed form averaged over a grid x grid set of positions in each pixel.
/// Inside a pixel the radiance is smooth except where the light's silhouette or the floor's edge crosses it; the
/// midpoint rule's error is O(h^2) on the smooth part but O(h) on such a step. Pixels whose grid sees both black and
/// lit floor are therefore averaged again over `fine` x `fine` positions (the step's error falls with the number
/// of rows it crosses, about fine^-1.5), so the reference stays far below the error of a 256-spp Sobol render.
Image exact_plane_image(const PlaneScene& ps, int size, int grid = 16, int fine = 256) {
  Image img(size, size);
  CameraRig rig = make_camera_rig(*ps.scene.camera, size, size);
  auto average = [&](int x, int y, int n, bool* mixed) {
    double sum = 0.0;
    int black = 0;
    for (int sy = 0; sy < n; ++sy)
      for (int sx = 0; sx < n; ++sx) {
        double v = exact_plane_radiance(ps, generate_camera_ray(rig, x, y, vec2((sx + 0.5f) / n, (sy + 0.5f) / n)));
        sum += v;
        black += v == 0.0;
      }
    if (mixed) *mixed = black > 0 && black < n * n;
    return sum / double(n) / double(n);
  };
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      bool mixed = false;
      double v = average(x, y, grid, &mixed);
      if (mixed && fine > grid) v = average(x, y, fine, nullptr);
      img.set(x, y, vec3(float(v)));
    }
  return img;
}

Image render(const RenderScene& rs, RenderParams p, int spp, Renderer& renderer) {
  Film film(p.width, p.height);
  RenderCounters c;
  p.spp_per_frame = spp;
  renderer.render_frame(rs, p, film, 0, c);
  return film.resolve();
}


// ---- Convergence (issue 12): the error estimator against the true error, and adaptive against uniform sampling.

/// A reference for a scene with no closed form: two MIS renders of spp / 2 samples (halves A and B, different
/// seeds, cached as `stem`-A.pfm and -B.pfm), averaged. Every rel_mse against it contains its own noise,
/// E[(x - r)^2] = Var(x) + Var(r); `noise` is that term in rel_mse units, (A - B)^2 / 4 normalised like rel_mse,
/// for the caller to subtract (issue 11: "the reference's own noise subtracted").
struct Reference {
  Image image;
  double noise = 0.0;
};

/// Mean over pixels and channels of (a - b)^2 / 4 / (r^2 + kRelMseFloor): for two independent renders a and b of equal
/// samples, the variance of their mean in rel_mse units (reference r).
double reference_noise(const Image& a, const Image& b, const Image& r) {
  double sum = 0.0;
  for (size_t i = 0; i < r.rgb.size(); ++i) {
    double d = double(a.rgb[i]) - double(b.rgb[i]), rr = double(r.rgb[i]);
    sum += d * d / 4.0 / (rr * rr + kRelMseFloor);
  }
  return r.rgb.empty() ? 0.0 : sum / double(r.rgb.size());
}

Reference cached_reference(const std::string& stem, const std::string& name, const RenderScene& rs,
                           const RenderParams& base, int spp, Renderer& renderer) {
  Image halves[2];
  for (int h = 0; h < 2; ++h) {
    std::string path = stem + (h == 0 ? "-A.pfm" : "-B.pfm");
    if (Result<Image> cached = load_image(path)) {
      halves[h] = std::move(*cached);
      continue;
    }
    auto t0 = std::chrono::steady_clock::now();
    RenderParams p = base;
    p.seed = 987654321 + uint64_t(h);
    halves[h] = render(rs, p, std::max(1, spp / 2), renderer);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("# reference %s half %c: %d spp in %.1f s -> %s\n", name.c_str(), 'A' + h, spp / 2, s,
                path.c_str());
    if (auto err = save_image(path, halves[h])) std::fprintf(stderr, "%s\n", err->message.c_str());
  }
  Reference ref{halves[0], 0.0};
  for (size_t i = 0; i < ref.image.rgb.size(); ++i)
    ref.image.rgb[i] = 0.5f * (halves[0].rgb[i] + halves[1].rgb[i]);
  ref.noise = reference_noise(halves[0], halves[1], ref.image);
  std::printf("# reference %s: %d spp, its own noise in rel_mse units %.3g (subtracted)\n", name.c_str(), spp,
              ref.noise);
  return ref;
}

/// est_rel_mse against the true rel_mse at 16, 64 and 256 spp, per scene and sampler, the mean over `seeds` seeds.
/// `pair` is a reference-free check: half the mean squared difference of two independent renders (seeds 2k and
/// 2k + 1), normalised like rel_mse. Several seeds because at 32x32 a few dozen pixels (a light's silhouette, a
/// caustic) hold most of the error, so one render's rel_mse, and its estimate, move by 20-50% from seed to seed.
void validate_estimator(const std::vector<std::pair<std::string, Reference>>& refs,
                        const std::vector<std::pair<std::string, const RenderScene*>>& scenes, int size,
                        int ref_spp, int seeds, Renderer& renderer, const std::string& csv_path) {
  std::ofstream csv(csv_path);
  csv << "scene,sampler,spp,ref_spp,rel_mse,est_rel_mse,pair_rel_mse,ratio\n";
  std::printf("\n# estimator validation: est_rel_mse / rel_mse (mean of %d seeds; target within [1/1.5, 1.5])\n",
              seeds);
  std::printf("%-22s %-12s %5s %11s %11s %11s %7s\n", "scene", "sampler", "spp", "rel_mse", "est_rel_mse", "pair",
              "ratio");
  for (size_t i = 0; i < scenes.size(); ++i) {
    const Image& ref = refs[i].second.image;
    for (auto [sampler_name, sampler] : kSamplers)
      for (int spp : {16, 64, 256}) {
        double rel = 0, est = 0;
        double pair = 0;
        Image img[2];
        for (int seed = 0; seed < seeds; ++seed) {
          RenderParams p;
          p.width = p.height = size;
          p.sampler = sampler;
          p.seed = uint64_t(seed) * 7919 + 11;
          p.spp_per_frame = spp;
          Film film(size, size);
          RenderCounters c;
          renderer.render_frame(*scenes[i].second, p, film, 0, c);
          img[seed % 2] = film.resolve();
          rel += (compare_images(img[seed % 2], ref).rel_mse - refs[i].second.noise) / seeds;
          est += est_rel_mse(film) / seeds;
          // Half the mean squared difference of the pair is twice the variance of their mean.
          if (seed % 2 == 1) pair += 2.0 * reference_noise(img[0], img[1], ref) / (seeds / 2);
        }
        csv << scenes[i].first << "," << sampler_name << "," << spp << "," << ref_spp << "," << rel << "," << est
            << "," << pair << "," << est / rel << "\n";
        std::printf("%-22s %-12s %5d %11.4g %11.4g %11.4g %7.3f\n", scenes[i].first.c_str(), sampler_name, spp, rel,
                    est, pair, est / rel);
      }
  }
}

/// Efficiency by scene, then by (strategy, sampler, spp): what the targets of issue 11 compare.
using EfficiencyTable =
    std::map<std::string, std::map<std::tuple<std::string, std::string, int>, std::vector<double>>>;

/// The median of one pair's efficiencies over the --repeat runs.
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Issue 11's targets 2 and 3 from one run's efficiencies, so that they are read off the bench's output instead of
/// worked out by hand: the defaults with Sobol against the best strategy and sampler pair at the largest spp
/// (target: at least 0.9 on every scene), and Sobol against independent numbers for the defaults at 16 spp (target:
/// at least 1.5 on the diffuse Cornell box). With --repeat 1 each ratio is one run against one run (or the best of
/// several, which favours the best pair by its luck), so it moves with the machine's timing noise; --repeat N takes
/// each pair's median over N runs with different seeds.
void print_targets(const EfficiencyTable& table, int max_spp, int repeat) {
  std::printf("\n# issue 11 target 2: defaults (sobol) against the best strategy and sampler pair at %d spp "
              "(target >= 0.9; median of %d runs)\n", max_spp, repeat);
  std::printf("%-20s %11s %-36s %11s %7s\n", "scene", "defaults", "best pair", "best", "ratio");
  for (const auto& [scene, rows] : table) {
    const auto defaults = rows.find({"defaults", "sobol", max_spp});
    if (defaults == rows.end()) continue;
    std::string best_name;
    double best = 0.0;
    for (const auto& [key, efficiencies] : rows) {
      if (std::get<2>(key) != max_spp) continue;
      const double m = median(efficiencies);
      if (m > best) best = m, best_name = std::get<0>(key) + ", " + std::get<1>(key);
    }
    const double ours = median(defaults->second);
    std::printf("%-20s %11.4g %-36s %11.4g %7.3f\n", scene.c_str(), ours, best_name.c_str(), best,
                best > 0.0 ? ours / best : 0.0);
  }
  std::printf("\n# issue 11 target 3: defaults, sobol against independent at 16 spp (target >= 1.5 on cornell)\n");
  std::printf("%-20s %11s %11s %7s\n", "scene", "sobol", "independent", "ratio");
  for (const auto& [scene, rows] : table) {
    const auto sobol = rows.find({"defaults", "sobol", 16}), independent = rows.find({"defaults", "independent", 16});
    if (sobol == rows.end() || independent == rows.end()) continue;
    const double s = median(sobol->second), i = median(independent->second);
    if (i > 0.0) std::printf("%-20s %11.4g %11.4g %7.3f\n", scene.c_str(), s, i, s / i);
  }
}

/// Seconds on the chosen clock: wall, or process CPU time / threads (see --clock).
double clock_seconds(bool cpu, int threads) {
  if (!cpu) return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec)) / double(threads);
}

/// Adaptive (--noise-threshold T) against uniform sampling on one scene: the adaptive run goes until every pixel
/// converged (or max_spp), then a uniform run gets the same render time. Efficiency = 1 / (rel_mse x seconds);
/// also at equal sample count (cost without timing noise).
void compare_adaptive(const std::string& name, const RenderScene& rs, const Reference& ref, int size, int max_spp,
                      Renderer& renderer, bool cpu_clock, const std::string& csv_path) {
  // rel_mse with the reference's own noise subtracted (see Reference).
  auto true_rel = [&](const Film& film) { return compare_images(film.resolve(), ref.image).rel_mse - ref.noise; };
  std::ofstream csv(csv_path);
  csv << "scene,mode,threshold,spp_mean,spp_max,seconds,rel_mse,est_rel_mse,converged_fraction\n";
  std::printf("\n# adaptive against uniform sampling at equal time, %s %dx%d (mis, sobol)\n", name.c_str(), size,
              size);
  std::printf("%-9s %9s %9s %7s %9s %11s %11s %9s %8s %8s\n", "mode", "threshold", "spp_mean", "spp_max", "seconds",
              "rel_mse", "est_rel_mse", "converged", "eff_t", "eff_spp");
  RenderParams p;
  p.width = p.height = size;
  p.spp_per_frame = 4;
  auto now = [&] { return clock_seconds(cpu_clock, renderer.thread_count()); };
  auto row = [&](const char* mode, double t, const ProgressiveFilm& f, double secs, double eff_t, double eff_s) {
    SppSummary s = spp_summary(f.film());
    double rel = true_rel(f.film()), est = est_rel_mse(f.film());
    csv << name << "," << mode << "," << t << "," << s.mean << "," << s.max << "," << secs << "," << rel << ","
        << est << "," << f.converged_fraction() << "\n";
    std::printf("%-9s %9.3g %9.1f %7u %9.2f %11.4g %11.4g %9.3f %8.2f %8.2f\n", mode, t, s.mean, s.max, secs, rel, est,
                f.converged_fraction(), eff_t, eff_s);
  };
  for (double t : {0.1, 0.05, 0.03}) {
    ProgressiveFilm a;
    a.reset(size, size);
    a.set_adaptive({t, 0});
    RenderCounters c;
    double ta = 0;
    while (!a.converged() && a.spp() < max_spp) {
      const double t0 = now();
      a.render_frame(renderer, rs, p, c);
      ta += now() - t0;
    }
    double rel_a = true_rel(a.film());
    // Uniform at equal time.
    ProgressiveFilm u;
    u.reset(size, size);
    double tu = 0;
    while (tu < ta) {
      const double t0 = now();
      u.render_frame(renderer, rs, p, c);
      tu += now() - t0;
    }
    double rel_u = true_rel(u.film());
    // Uniform at equal samples: the adaptive run's mean spp (rounded up to a multiple of 4).
    ProgressiveFilm e;
    e.reset(size, size);
    double mean_a = spp_summary(a.film()).mean, te = 0;
    while (e.spp() < mean_a) {
      const double t0 = now();
      e.render_frame(renderer, rs, p, c);
      te += now() - t0;
    }
    double rel_e = true_rel(e.film());
    double eff_t = (rel_u * tu) / (rel_a * ta), eff_s = (rel_e * spp_summary(e.film()).mean) / (rel_a * mean_a);
    row("adaptive", t, a, ta, eff_t, eff_s);
    row("uniform", 0, u, tu, 1, 1);
    row("uni-spp", 0, e, te, 1, 1);
  }
}

}  // namespace

/// The issue-11 scene: the 36-triangle Cornell box OBJ with its two-triangle ceiling light emitting.
Result<Scene> make_cornell36_scene() {
  Result<Scene> s = load_scene(std::string(PTVIEW_SOURCE_DIR) + "/bench/data/cornell36.json");
  if (!s) return s;
  s->background.reset();
  for (Material& m : s->materials)
    if (m.name == "light") m.emission = vec3(17, 12, 4);
  s->source = "cornell36";
  return s;
}

/// Sobol's cost against independent numbers, with the defaults: frames of 1 spp rendered alternately with each
/// sampler (the order swapped every frame), so a change in the machine's load hits both alike; prints the spp/s
/// ratio Sobol / independent (issue 11, target 3).
void sampler_cost(const std::string& name, const RenderScene& rs, int size, int max_depth, int frames, bool cpu_clock,
                  Renderer& renderer) {
  double seconds[2] = {0.0, 0.0};
  Film films[2] = {Film(size, size), Film(size, size)};
  RenderCounters c;
  for (int f = 0; f < frames; ++f)
    for (int j = 0; j < 2; ++j) {
      const int k = (f + j) & 1;
      RenderParams p;
      p.width = p.height = size;
      p.max_depth = max_depth;
      p.sampler = kSamplers[k].second;
      double t0 = clock_seconds(cpu_clock, renderer.thread_count());
      renderer.render_frame(rs, p, films[k], uint32_t(f), c);
      seconds[k] += clock_seconds(cpu_clock, renderer.thread_count()) - t0;
    }
  std::printf("%-20s sampler cost, %d frames of %dx%d: independent %.1f spp/s, sobol %.1f spp/s, ratio %.3f\n",
              name.c_str(), frames, size, size, frames / seconds[0], frames / seconds[1], seconds[0] / seconds[1]);
}

int main(int argc, char** argv) {
  int size = 128, max_spp = 256, ref_spp = 4096, max_depth = 64, threads = 0;
  std::string cache = std::string(std::getenv("HOME") ? std::getenv("HOME") : "/tmp") + "/.cache/ptview";
  std::string csv_path = "time_vs_error.csv";
  std::string only;
  bool cpu_clock = false;
  std::string clock_arg = "wall";
  std::string only_strategies;
  uint64_t seed = 0;  // of the measured renders (the references have their own)
  int repeat = 1;     // runs of every pair for the target summary (their median)
  int max_frames_per_pass = kMaxFramesPerPass;  // 1: a frame per pass, as before the fourteenth round
  int sampler_cost_frames = 0;
  // Convergence sections: "estimator", "adaptive", "both", "only" (both, skipping the strategy curves) or "none".
  std::string convergence = "both";
  int conv_size = 32, conv_ref_spp = 4096, conv_seeds = 8;
  std::string scenes_arg, strategies_arg;
  CLI::App app{"Error against time for every sampling strategy and sampler, then issue 11's targets 2 and 3 and the "
               "convergence sections (see the comment at the top of bench/time_vs_error.cpp).",
               "bench_time_vs_error"};
  app.add_option("--size", size, "Image width and height (default 128)")->check(CLI::Range(1, 8192));
  app.add_option("--max-spp", max_spp, "Last spp count of the curves (default 256)")->check(CLI::Range(1, 1 << 20));
  app.add_option("--ref-spp", ref_spp, "Samples of a rendered reference (default 4096)")->check(CLI::Range(2, 1 << 24));
  app.add_option("--cache", cache, "Directory of the cached references (default ~/.cache/ptview)");
  app.add_option("--csv", csv_path, "CSV of the curves (default time_vs_error.csv)");
  app.add_option("--scenes", scenes_arg, "Comma-separated scenes (default: all but cornell36)");
  app.add_option("--convergence", convergence, "Convergence sections (default both)")
      ->check(CLI::IsMember({"estimator", "adaptive", "both", "only", "none"}));
  app.add_option("--conv-size", conv_size, "Image size of the convergence sections (default 32)")
      ->check(CLI::Range(1, 8192));
  app.add_option("--conv-ref-spp", conv_ref_spp, "Their references' spp (default 4096)")->check(CLI::Range(2, 1 << 24));
  app.add_option("--conv-seeds", conv_seeds, "Seeds the estimator section averages over (default 8; rounded to even)")
      ->check(CLI::Range(2, 1 << 16));
  app.add_option("--max-depth", max_depth, "Maximum path depth (default 64)")->check(CLI::Range(1, 1 << 16));
  app.add_option("--threads", threads, "Worker threads (default 0: all cores)")->check(CLI::Range(0, 1 << 10));
  app.add_option("--clock", clock_arg, "wall (default) or cpu: process CPU seconds over the thread count")
      ->check(CLI::IsMember({"wall", "cpu"}));
  app.add_option("--strategies", strategies_arg, "Comma-separated strategies (default: all)");
  app.add_option("--seed", seed, "Seed of the measured renders (default 0)");
  app.add_option("--repeat", repeat, "Runs of every pair for the target summary (default 1)")->check(CLI::Range(1, 1000));
  app.add_option("--max-frames-per-pass", max_frames_per_pass, "Frames rendered as one pass (default 16)")
      ->check(CLI::Range(1, 1 << 16));
  app.add_option("--sampler-cost", sampler_cost_frames, "Only Sobol's frame time against independent's, N frames")
      ->check(CLI::Range(0, 1 << 20));
  if (std::optional<int> exit_code = bench::parse_command_line(app, argc, argv)) return *exit_code;
  cpu_clock = clock_arg == "cpu";
  conv_seeds = conv_seeds / 2 * 2;
  if (!scenes_arg.empty()) only = "," + scenes_arg + ",";
  if (!strategies_arg.empty()) only_strategies = "," + strategies_arg + ",";
  std::vector<std::string> strategy_names;
  for (const Strategy& st : kStrategies) strategy_names.push_back(st.name);
  if (std::string bad = bench::check_names("--strategies", strategies_arg, strategy_names); !bad.empty()) {
    std::fprintf(stderr, "bench_time_vs_error: %s\n", bad.c_str());
    return 2;
  }
  std::vector<std::pair<std::string, Scene>> scenes;
  for (const char* name : {"cornell", "cornell-glass", "cornell-mirror", "cornell-large-mesh"}) {
    Result<Scene> s = load_builtin_scene(name);
    if (s) scenes.emplace_back(name, std::move(*s));
  }
  scenes.emplace_back("small-bright-light", make_small_light_scene());
  scenes.emplace_back("furnace", make_furnace_scene());
  PlaneScene plane = make_plane_scene();
  scenes.emplace_back("rect-light-over-plane", plane.scene);
  if (only.find(",cornell36,") != std::string::npos) {
    Result<Scene> c36 = make_cornell36_scene();
    if (!c36) {
      std::fprintf(stderr, "%s\n", c36.error().c_str());
      return 2;
    }
    scenes.emplace_back("cornell36", std::move(*c36));
  }
  std::vector<std::string> scene_names{"cornell36"};  // loaded above only when asked for
  for (const auto& named : scenes)
    if (named.first != "cornell36") scene_names.push_back(named.first);
  if (std::string bad = bench::check_names("--scenes", scenes_arg, scene_names); !bad.empty()) {
    std::fprintf(stderr, "bench_time_vs_error: %s\n", bad.c_str());
    return 2;
  }
  Renderer renderer(threads);
  if (sampler_cost_frames > 0) {
    for (auto& [name, scene] : scenes)
      if (only.empty() || only.find("," + name + ",") != std::string::npos)
        sampler_cost(name, make_render_scene(scene), size, max_depth, sampler_cost_frames, cpu_clock, renderer);
    return 0;
  }
  fs::create_directories(cache);
  std::ofstream csv(csv_path);
  csv << "scene,strategy,sampler,spp,seconds,rmse,rel_mse,rel_mse_raw,efficiency\n";
  std::printf("%-20s %-22s %-12s %6s %9s %11s %11s %11s\n", "scene", "strategy", "sampler", "spp", "seconds", "rmse",
              "rel_mse", "efficiency");
  EfficiencyTable efficiencies;
  for (auto& [name, scene] : scenes) {
    if (convergence == "only") break;
    if (!only.empty() && only.find("," + name + ",") == std::string::npos) continue;
    RenderScene rs = make_render_scene(scene);
    std::printf("# %s: automatic light sampling at the first vertex: min spread %g (pilot gain %.3g)\n", name.c_str(),
                rs.auto_first_spread, rs.auto_pilot_gain);
    RenderParams base;
    base.width = base.height = size;
    base.max_depth = max_depth;
    base.threads = threads;
    base.seed = seed;
    Image reference;
    double ref_noise = 0.0;
    if (name == "furnace") {
      reference = Image(size, size);
      std::fill(reference.rgb.begin(), reference.rgb.end(), 1.0f);
    } else if (name == "rect-light-over-plane") {
      reference = exact_plane_image(plane, size);
    } else {
      Reference ref = cached_reference(cache + "/ref-" + name + "-" + std::to_string(size) + "-d" +
                                           std::to_string(max_depth) + "-" + std::to_string(ref_spp),
                                       name, rs, base, ref_spp, renderer);
      reference = std::move(ref.image);
      ref_noise = ref.noise;
    }
    // Repeats go round all pairs in turn, so that a slow spell of the machine falls on every pair alike. Only the
    // first run's rows are printed and written to the CSV; the others feed the target summary's medians.
    for (int rep = 0; rep < repeat; ++rep)
      for (const Strategy& st : kStrategies)
        for (auto [sampler_name, sampler] : kSamplers) {
          if (!only_strategies.empty() && only_strategies.find("," + std::string(st.name) + ",") == std::string::npos)
            continue;
          RenderParams p = base;
          p.seed = base.seed + uint64_t(rep) * 1000003u;
          p.integrator = st.integrator;
          p.light_sampling = st.light_sampling;
          p.sampler = sampler;
          Film film(size, size);
          RenderCounters c;
          double seconds = 0;
          int next_report = 1;
          // Passes of several frames, as `ptview --frames N` renders them (app/headless.cpp: about
          // kHeadlessPassSeconds at the time per frame so far, one frame of `pass` samples a pixel continuing from
          // each pixel's next sample index), ending at every reported spp count. The film is the one a frame at a
          // time gives, bit for bit.
          for (int spp = 0; spp < max_spp;) {
            const int pass = std::min({frames_for_pass_time(spp > 0 ? seconds / spp : 0.0, kHeadlessPassSeconds),
                                       max_frames_per_pass, next_report - spp, max_spp - spp});
            p.spp_per_frame = pass;
            double t0 = clock_seconds(cpu_clock, renderer.thread_count());
            renderer.render_pass(rs, p, film, nullptr, c);
            seconds += clock_seconds(cpu_clock, renderer.thread_count()) - t0;
            spp += pass;
            if (spp != next_report) continue;
            next_report *= 2;
            ImageError e = compare_images(film.resolve(), reference);
            double rel = e.rel_mse - ref_noise;
            double efficiency = rel > 0.0 && seconds > 0.0 ? 1.0 / (rel * seconds) : 0.0;
            efficiencies[name][{st.name, sampler_name, spp}].push_back(efficiency);
            if (rep > 0) continue;
            csv << name << "," << st.name << "," << sampler_name << "," << spp << "," << seconds << "," << e.rmse
                << "," << rel << "," << e.rel_mse << "," << efficiency << "\n";
            std::printf("%-20s %-22s %-12s %6d %9.3f %11.4g %11.4g %11.4g\n", name.c_str(), st.name, sampler_name,
                        spp, seconds, e.rmse, rel, efficiency);
          }
        }
  }
  if (!efficiencies.empty()) print_targets(efficiencies, max_spp, repeat);
  std::printf("wrote %s\n", csv_path.c_str());
  if (convergence == "none") return 0;
  const std::string stem = csv_path.substr(0, csv_path.rfind('.'));
  std::vector<std::pair<std::string, Reference>> refs;
  std::vector<std::unique_ptr<RenderScene>> owned;
  std::vector<std::pair<std::string, const RenderScene*>> conv_scenes;
  for (auto& [name, scene] : scenes) {
    if (name != "rect-light-over-plane" && name.rfind("cornell", 0) != 0) continue;
    if (name == "cornell-large-mesh") continue;  // same light transport as cornell, much slower references
    owned.push_back(std::make_unique<RenderScene>(make_render_scene(scene)));
    conv_scenes.emplace_back(name, owned.back().get());
    RenderParams base;
    base.width = base.height = conv_size;
    refs.emplace_back(name, name == "rect-light-over-plane"
                                ? Reference{exact_plane_image(plane, conv_size, 64, 1024), 0.0}  // see its comment
                                : cached_reference(cache + "/ref-" + name + "-" + std::to_string(conv_size) + "-" +
                                                       std::to_string(conv_ref_spp),
                                                   name, *owned.back(), base, conv_ref_spp, renderer));
  }
  if (convergence != "adaptive")
    validate_estimator(refs, conv_scenes, conv_size, conv_ref_spp, conv_seeds, renderer, stem + "-estimator.csv");
  if (convergence != "estimator")
    for (size_t i = 0; i < conv_scenes.size(); ++i)
      if (conv_scenes[i].first == "cornell-glass")
        compare_adaptive("cornell-glass", *conv_scenes[i].second, refs[i].second, conv_size, 2048, renderer, cpu_clock,
                         stem + "-adaptive.csv");
  return 0;
}
