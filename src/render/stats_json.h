#pragma once
/// The stats JSON object (see README): one builder for headless runs and the viewer, which adds its own keys.
#include <cmath>
#include <limits>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/adaptive.h"
#include "render/convergence.h"
#include "render/render_params.h"
#include "render/render_scene.h"
#include "render/stats.h"

namespace pt {

/// Time and samples of one rank of a distributed run (src/dist), for the stats JSON.
struct RankWork {
  int spp = 0;
  double seconds = 0.0;
};

/// How converged a film is (render/convergence.h, render/adaptive.h), for the stats JSON.
struct ConvergenceSummary {
  double est_rel_mse = std::numeric_limits<double>::quiet_NaN();  ///< NaN when unknown (written as null)
  double converged_fraction = 0.0;
  SppSummary spp;
  double noise_threshold = 0.0;  ///< 0: adaptive sampling off
  int min_spp = 0;
};
ConvergenceSummary summarize_convergence(const ProgressiveFilm& film);

/// Summary of a run (headless) or of the current epoch (viewer), for --stats-json.
struct RunSummary {
  int frames = 0;
  int spp = 0;
  double seconds = 0.0;       ///< rendering time, excluding loading and BVH build
  double load_ms = 0.0;
  RenderCounters counters;
  int threads = 1;
  uint64_t epoch = 0;         ///< viewer: restarts so far (headless: 0)
  ConvergenceSummary convergence;
  std::vector<RankWork> per_rank;  ///< spp and seconds of every rank (empty: one process, this one)
  double comm_ms = 0.0;            ///< rank 0's time in MPI calls
};

/// spp, seconds, rays, mrays_per_s, nonfinite_samples, bvh, skipped, kernel, features, warnings, ...
nlohmann::json make_stats_json(const RenderParams& params, const Scene& scene, const RenderScene& rs,
                               const RunSummary& run);

}  // namespace pt
