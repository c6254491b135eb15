#include "render/auto_light_sampling.h"

#include <algorithm>
#include <cmath>

#include "render/camera.h"
#include "render/image_error.h"
#include "render/integrator.h"

namespace pt {

namespace {

/// Pilot size: kGrid x kGrid pixel centers of a kGrid x kGrid image, kSamples paths each with each threshold: 2 x 1024
/// paths, 1.4-3 ms on bench-error's scenes, so a camera edit in the viewer stays instant. 16 samples per pixel
/// rather than 4 at 16 x 16 pixels: the per-pixel variances are then less short of the heavy tails (the gain read on
/// the Cornell scenes over five seeds fell from at most 0.087 to at most 0.067, with the channels' mean as the pixel
/// value; per channel, as now, at most 0.047).
constexpr int kGrid = 8;
constexpr int kSamples = 16;
/// Deep vertices add little to a pixel's variance under roulette; the bound keeps the pilot's cost bounded in closed
/// rooms of white walls, where paths would otherwise run to the default depth of 64.
constexpr int kMaxDepth = 16;
constexpr uint64_t kPilotSeed = 0x9170c0ffee5eedull;

bool affects_lights(const LightSet& lights) {
  return std::any_of(lights.lights.begin(), lights.lights.end(),
                     [](const Light& l) { return l.kind != LightKind::sphere; });
}

}  // namespace

AutoLightSamplingChoice choose_auto_light_sampling(const RenderScene& rs) {
  AutoLightSamplingChoice choice;
  if (!affects_lights(rs.lights)) {
    choice.gain = std::numeric_limits<float>::quiet_NaN();
    return choice;
  }
  RenderParams params;  // the defaults: automatic integrator (NEE under automatic light sampling)
  params.width = params.height = kGrid;
  params.max_depth = kMaxDepth;
  params.sampler = SamplerKind::independent;
  const CameraRig rig = make_camera_rig(rs.camera, kGrid, kGrid);
  RenderCounters counters;
  double removed = 0.0, total = 0.0;
  for (int y = 0; y < kGrid; ++y)
    for (int x = 0; x < kGrid; ++x) {
      const uint64_t pixel = uint64_t(y) * kGrid + uint64_t(x);
      const Ray ray = generate_camera_ray(rig, x, y, vec2(0.5f));
      dvec3 sum[2] = {dvec3(0.0), dvec3(0.0)}, sum2[2] = {dvec3(0.0), dvec3(0.0)};
      int n = 0;
      for (int s = 0; s < kSamples; ++s) {
        // The same numbers for both thresholds: the paths differ only in the first vertex's light sample.
        PixelSampler area = PixelSampler::start(kPilotSeed, pixel, uint64_t(s), params.sampler), solid = area;
        const vec3 la = trace_path(rs, params, kAutoMinSpreadDeep, ray, area, counters);
        const vec3 ls = trace_path(rs, params, kAutoMinSpread, ray, solid, counters);
        if (!is_finite(la) || !is_finite(ls)) continue;
        const dvec3 v[2] = {dvec3(la), dvec3(ls)};
        for (int k = 0; k < 2; ++k) sum[k] += v[k], sum2[k] += v[k] * v[k];
        ++n;
      }
      if (n < 2) continue;
      dvec3 var[2];
      for (int k = 0; k < 2; ++k)
        var[k] = glm::max(dvec3(0.0), (sum2[k] - sum[k] * sum[k] / double(n)) / double(n - 1));
      // Per channel, as rel_mse weighs a pixel (render/image_error.h); the mean of both runs is a steadier weight.
      const dvec3 mean = (sum[0] + sum[1]) / double(2 * n);
      const dvec3 weight = 1.0 / (mean * mean + kRelMseFloor);
      removed += glm::dot(weight, var[0] - var[1]);
      total += glm::dot(weight, var[0]);
    }
  choice.gain = total > 0.0 && std::isfinite(removed / total) ? float(removed / total) : 0.0f;
  choice.first_spread = choice.gain >= kAutoMinGain ? kAutoMinSpread : kAutoMinSpreadDeep;
  return choice;
}

void update_auto_light_sampling(RenderScene& rs) {
  const AutoLightSamplingChoice c = choose_auto_light_sampling(rs);
  rs.auto_first_spread = c.first_spread;
  rs.auto_pilot_gain = c.gain;
  rs.auto_pilot_pending = false;
}

}  // namespace pt
