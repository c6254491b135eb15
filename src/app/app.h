#pragma once
/// Entry points of the program: parse, load, then run headless or open the viewer.
#include "app/options.h"
#include "render/render_scene.h"
#include "render/stats.h"

namespace pt {

/// The whole program; returns the process exit code (0 ok, 2 bad input or failure).
int run_app(int argc, const char* const* argv);

/// Renders options.frames frames (or until the time limit) without a window, writes outputs; returns exit code.
/// `load_ms`: how long reading and parsing the scene took (the caller loaded it), reported as the stats' load_ms.
int run_headless(const AppOptions& options, const Scene& scene, double load_ms = 0.0);

/// Summary of a finished run, for --stats-json.
struct RunSummary {
  int frames = 0;
  int spp = 0;
  double seconds = 0.0;       ///< rendering time, excluding loading and BVH build
  double load_ms = 0.0;       ///< reading and parsing the scene file (not the BVH build: bvh.build_ms)
  RenderCounters counters;
  int threads = 1;
};

/// The stats JSON object (see README): spp, seconds, rays, mrays_per_s, nonfinite_samples, bvh, skipped, ...
std::string make_stats_json(const AppOptions& options, const Scene& scene, const RenderScene& rs,
                            const RunSummary& run);

/// Root-mean-square error and relative MSE (mean of (x - r)^2 / (r^2 + 0.01) over pixels and channels).
struct ImageError {
  double rmse = 0.0;
  double rel_mse = 0.0;
};
ImageError compare_images(const Image& image, const Image& reference);

}  // namespace pt
