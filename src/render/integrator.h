#pragma once
/// The unidirectional path tracer: next-event estimation, BSDF sampling, or both combined by multiple importance
/// sampling with the power heuristic (Veach 1997, chapter 9; pbrt-v4 section 13.4). Emission is counted exactly
/// once per path under every strategy.
#include "render/render_params.h"
#include "render/render_scene.h"
#include "render/sampler.h"
#include "render/stats.h"

namespace pt {

/// Radiance arriving along `ray` (from the camera). Counters are updated; the caller drops non-finite results.
vec3 trace_path(const RenderScene& scene, const RenderParams& params, Ray ray, PixelSampler& sampler,
                RenderCounters& counters);

/// Which specialization of the path loop trace_path runs for this scene (for stats).
const char* kernel_name(const RenderScene& scene, const RenderParams& params);

/// Power heuristic with beta = 2 for one sample from each strategy.
inline float power_heuristic(float pdf_a, float pdf_b) {
  float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  if (std::isinf(a)) return 1.0f;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

}  // namespace pt
