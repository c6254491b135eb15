#pragma once
/// Entry points of the program: parse, load, then run headless or open the viewer.
#include <limits>
#include <nlohmann/json_fwd.hpp>

#include "app/options.h"
#include "render/convergence.h"
#include "dist/cluster.h"
#include "render/render_scene.h"
#include "render/stats.h"

namespace pt {

/// The whole program; returns the process exit code (0 ok, 2 bad input or failure).
int run_app(int argc, const char* const* argv);

/// Renders options.frames frames (or until the time limit) without a window, writes outputs; returns exit code.
/// With several ranks (src/dist), each renders its share of the frames and rank 0 writes the outputs.
int run_headless(const AppOptions& options, const Scene& scene, Cluster& cluster);

/// How converged a film is (render/convergence.h, render/adaptive.h), for the stats JSON.
struct ConvergenceSummary {
  double est_rel_mse = std::numeric_limits<double>::quiet_NaN();  ///< NaN when unknown (written as null)
  double converged_fraction = 0.0;
  SppSummary spp;
  double noise_threshold = 0.0;     ///< 0: adaptive sampling off
  int min_spp = 0;
};
ConvergenceSummary summarize_convergence(const ProgressiveFilm& film);
/// Adds est_rel_mse, converged_fraction, spp_min, spp_max, spp_mean and, with adaptive sampling, noise_threshold
/// and min_spp to a stats object (shared by the headless and the viewer stats).
void add_convergence_stats(nlohmann::json& j, const ConvergenceSummary& c);

/// Summary of a finished run, for --stats-json.
struct RunSummary {
  int frames = 0;
  int spp = 0;
  double seconds = 0.0;       ///< rendering time, excluding loading and BVH build
  double load_ms = 0.0;
  RenderCounters counters;
  int threads = 1;
  ConvergenceSummary convergence;
  std::vector<RankWork> per_rank;  ///< spp and seconds of every rank (one entry without MPI)
  double comm_ms = 0.0;         ///< rank 0's time in MPI calls
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
