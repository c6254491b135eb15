#pragma once
/// The stats JSON object (see README): one builder for headless runs and the viewer, which adds its own keys.
#include <nlohmann/json.hpp>

#include "render/render_params.h"
#include "render/render_scene.h"
#include "render/stats.h"

namespace pt {

/// Summary of a run (headless) or of the current epoch (viewer), for --stats-json.
struct RunSummary {
  int frames = 0;
  int spp = 0;
  double seconds = 0.0;       ///< rendering time, excluding loading and BVH build
  double load_ms = 0.0;
  RenderCounters counters;
  int threads = 1;
  uint64_t epoch = 0;         ///< viewer: restarts so far (headless: 0)
};

/// spp, seconds, rays, mrays_per_s, nonfinite_samples, bvh, skipped, kernel, features, warnings, ...
nlohmann::json make_stats_json(const RenderParams& params, const Scene& scene, const RenderScene& rs,
                               const RunSummary& run);

}  // namespace pt
