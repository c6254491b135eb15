#pragma once
/// LightSampling::automatic's choice per scene and camera: whether the first non-delta vertex of a path samples a
/// light by solid angle (where area sampling's density spreads by at least kAutoMinSpread) or only close to a light,
/// as deeper vertices do (kAutoMinSpreadDeep).
///
/// Why per scene: solid-angle sampling lowers the variance of direct light only. Where direct light at the first
/// vertex is most of a pixel's variance (a surface under a large light, nothing else lit) it is worth several times
/// its cost; where indirect light dominates (every Cornell box of bench-error) it changes rel_mse in the fourth digit
/// and costs 6-8% of the frame time, so the defaults lost to NEE with area sampling (issue 11, target 2). A
/// per-receiver test alone cannot tell the two apart: the receivers see the light alike, only the rest of the
/// scene differs.
///
/// How: a pilot traces a few paths through a grid of pixel centers, each twice with the same random numbers, once
/// with each first-vertex threshold. Under NEE the two paths differ only in the first vertex's light sample, so
/// their variances differ by what solid-angle sampling removes there. The choice is solid angle when that is at least
/// kAutoMinGain of the variance, weighted per pixel as rel_mse weights it (the pixels are the centers of an 8 x 8
/// grid over the central square of the view). The pilot is deterministic (a fixed seed,
/// one thread), so every thread, rank and offload host makes the same choice for the same scene and camera, and the
/// estimator stays unbiased: the choice does not depend on the samples it is used for.
#include "render/render_scene.h"

namespace pt {

/// The share of the image's variance that solid-angle sampling at the first vertex must remove to be chosen. Its
/// cost where most first vertices use it is 6-8% of the frame time (bench-error's Cornell scenes), so by cost alone
/// the break-even gain is about 0.07. But the pilot's 16 samples per pixel under-count heavy-tailed indirect light
/// (through glass, off mirrors), which inflates its gain: over five pilot seeds it reads 0.0015-0.047 on the Cornell
/// scenes, where full renders measure 0.001-0.016, and 0.935-0.947 on the lit plane, all direct light, where full
/// renders measure 0.93. 0.2 keeps the first kind out with a margin of four and the second in with one of 4.7
/// (docs/BENCHMARKS.md, "Tenth round" and "Eleventh round").
inline constexpr float kAutoMinGain = 0.2f;

struct AutoLightSamplingChoice {
  float first_spread = kAutoMinSpread;  ///< the first vertex's spread threshold chosen
  float gain = 0.0f;                    ///< the estimated share of variance removed (NaN: not measured)
};

/// Runs the pilot on `rs` (its camera, lights and materials as they are) and returns the choice. Scenes without a
/// rectangle, parallelogram or triangle light (whose sampling the threshold affects) keep kAutoMinSpread, unmeasured.
AutoLightSamplingChoice choose_auto_light_sampling(const RenderScene& rs);

/// Sets rs.auto_first_spread and rs.auto_pilot_gain from choose_auto_light_sampling.
void update_auto_light_sampling(RenderScene& rs);

}  // namespace pt
