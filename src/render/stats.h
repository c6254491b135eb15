#pragma once
/// Counters of the work done and the work skipped. Each worker fills its own and they are summed after a tile,
/// so counting costs no atomics in the hot loop.
#include <cstdint>
#include <utility>
#include <vector>

namespace pt {

struct RenderCounters {
  uint64_t samples = 0;            ///< camera samples taken (including dropped ones)
  uint64_t camera_rays = 0;
  uint64_t bounce_rays = 0;        ///< closest-hit rays after the first
  uint64_t shadow_rays = 0;
  uint64_t nonfinite_samples = 0;  ///< dropped, never averaged into the image
  // Work skipped, and why:
  uint64_t shadow_skipped_backfacing = 0;  ///< light sample faced away or was behind the surface: no shadow ray
  uint64_t shadow_skipped_zero_bsdf = 0;   ///< BSDF was zero toward the light sample: no shadow ray
  uint64_t light_sampling_skipped_specular = 0;  ///< vertex on a mirror or glass: light sampling not attempted
  uint64_t paths_ended_roulette = 0;
  uint64_t paths_ended_max_depth = 0;
  uint64_t paths_escaped = 0;
  /// The BSDF sample failed (below the surface, or a mirror or glass turned by a shading normal) or left no
  /// positive finite throughput (a black surface). With the three above, every sample's path ends for exactly one
  /// counted reason.
  uint64_t paths_ended_absorbed = 0;

  uint64_t rays() const { return camera_rays + bounce_rays + shadow_rays; }
  RenderCounters& operator+=(const RenderCounters& o) {
    samples += o.samples;
    camera_rays += o.camera_rays;
    bounce_rays += o.bounce_rays;
    shadow_rays += o.shadow_rays;
    nonfinite_samples += o.nonfinite_samples;
    shadow_skipped_backfacing += o.shadow_skipped_backfacing;
    shadow_skipped_zero_bsdf += o.shadow_skipped_zero_bsdf;
    light_sampling_skipped_specular += o.light_sampling_skipped_specular;
    paths_ended_roulette += o.paths_ended_roulette;
    paths_ended_max_depth += o.paths_ended_max_depth;
    paths_escaped += o.paths_escaped;
    paths_ended_absorbed += o.paths_ended_absorbed;
    return *this;
  }
};

/// The counters of skipped work under the names every report uses (stats JSON of headless runs and the viewer).
inline std::vector<std::pair<const char*, uint64_t>> skipped_work(const RenderCounters& c) {
  return {{"shadow_rays_backfacing", c.shadow_skipped_backfacing},
          {"shadow_rays_zero_bsdf", c.shadow_skipped_zero_bsdf},
          {"light_sampling_specular", c.light_sampling_skipped_specular},
          {"paths_ended_roulette", c.paths_ended_roulette},
          {"paths_ended_max_depth", c.paths_ended_max_depth},
          {"paths_escaped", c.paths_escaped},
          {"paths_ended_absorbed", c.paths_ended_absorbed}};
}

}  // namespace pt
