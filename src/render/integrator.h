#pragma once
/// The unidirectional path tracer: next-event estimation, BSDF sampling, or both combined by multiple importance
/// sampling with the power heuristic (Veach 1997, chapter 9; pbrt-v4 section 13.4). Emission is counted exactly
/// once per path under every strategy.
#include "render/render_params.h"
#include "render/render_scene.h"
#include "render/sampler.h"
#include "render/stats.h"

namespace pt {

/// Radiance arriving along the ray (org, dir, tmax) from the camera, with the first non-delta vertex's automatic
/// spread threshold `first_vertex_spread` (RenderScene::auto_first_spread, or what the pilot of
/// render/auto_light_sampling.h compares). Counters are updated; the caller drops non-finite results.
/// The ray comes as vectors, not as a Ray: a struct of 28 bytes is passed in memory, and reading it back as 16-byte
/// words right after the caller wrote it field by field stalled store forwarding on every pixel sample (this
/// function was 10% of a frame where most camera rays escape; docs/BENCHMARKS.md, fourteenth round). Vectors and
/// floats travel in registers.
vec3 trace_path(const RenderScene& scene, const RenderParams& params, float first_vertex_spread, vec3 org, vec3 dir,
                float tmax, PixelSampler& sampler, RenderCounters& counters);
inline vec3 trace_path(const RenderScene& scene, const RenderParams& params, float first_vertex_spread,
                       const Ray& ray, PixelSampler& sampler, RenderCounters& counters) {
  return trace_path(scene, params, first_vertex_spread, ray.org, ray.dir, ray.tmax, sampler, counters);
}
inline vec3 trace_path(const RenderScene& scene, const RenderParams& params, const Ray& ray, PixelSampler& sampler,
                       RenderCounters& counters) {
  return trace_path(scene, params, scene.auto_first_spread, ray.org, ray.dir, ray.tmax, sampler, counters);
}

/// The integrator `kind` stands for: itself, or for automatic, nee unless lights are sampled by area. Why: every
/// light has a solid-angle sampling (spheres by their cone, rectangles, parallelograms and triangles by spherical
/// ones), which light_sampling solid_angle uses everywhere and automatic wherever area sampling's density is far from
/// it (elsewhere the two agree within the spread threshold, light.h). The scenes have only diffuse, mirror and glass
/// surfaces; mirror and glass cannot be light-sampled, so both strategies count emission after them in full, and at
/// a diffuse vertex a solid-angle light sample already has a density close to the integrand, so MIS only adds the
/// BSDF-side light_pdf evaluation and weights that move variance onto cosine-sampled hits (bench-error, issue 11:
/// nee beat mis on every Cornell scene). With --light-sampling area the light sample's density blows up near the
/// light's plane and MIS's BSDF side is what bounds it.
IntegratorKind resolve_integrator(IntegratorKind kind, LightSampling light_sampling);

/// Which specialization of the path loop trace_path runs for this scene (for stats).
const char* kernel_name(const RenderScene& scene, const RenderParams& params);

/// Russian roulette's survival factor: a path survives with probability min(1, kRouletteBoost x the largest
/// component of its throughput, eta^2 scaling undone). Why not the throughput itself (pbrt-v4 section 13.4.4, factor
/// 1): take one roulette decision with survival s at throughput beta, the rest of the path having second moment M and
/// cost C, the whole sample variance V and cost T. Then variance x cost is (V + beta^2 M (1/s - 1)) (T - C (1 - s)),
/// least at s = beta sqrt(M (T - C) / ((V - beta^2 M) C)): proportional to the throughput, with a factor set by the
/// scene (Rath et al. 2022, "EARS: Efficiency-Aware Russian Roulette and Splitting", learn such factors per region).
/// That factor is 1 only by chance; where indirect light is much of a pixel (every Cornell scene) it is well above
/// 1, and factor 1 ends paths that were cheap to continue: 1.5-2x the variance for 1.2-1.4x the speed. Measured with
/// `make bench-error` and `make bench-cornell36` (docs/BENCHMARKS.md, "Eighth round"): efficiency peaks between 2
/// and 4 on every scene and 3 gains 9-43% over 1, while no roulette at all is 30-42% below 3 at depth 64. A factor
/// learned per scene or region, as EARS does, is not attempted.
inline constexpr float kRouletteBoost = 3.0f;

/// The survival probability for a path whose throughput's largest component (eta^2 scaling undone) is rr_max;
/// 1 or more means no roulette.
inline float roulette_survival(float rr_max) { return kRouletteBoost * rr_max; }

/// Power heuristic with beta = 2 for one sample from each strategy.
inline float power_heuristic(float pdf_a, float pdf_b) {
  float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  if (std::isinf(a)) return 1.0f;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

}  // namespace pt
