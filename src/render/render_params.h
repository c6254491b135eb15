#pragma once
/// The parameters of one render: shared by the command line, the headless runner and the viewer.
#include <cstdint>

#include "render/light.h"
#include "render/sampler.h"

namespace pt {

/// automatic (the default) picks nee, or mis under area light sampling: see resolve_integrator (render/integrator.h).
enum class IntegratorKind : int { mis = 0, nee = 1, bsdf = 2, automatic = 3 };

struct RenderParams {
  int width = 512;
  int height = 512;
  int spp_per_frame = 1;
  int max_depth = 64;  ///< pbrt's convention: 0 = emission seen directly, 1 = plus direct lighting, ...
  IntegratorKind integrator = IntegratorKind::automatic;
  LightSampling light_sampling = LightSampling::automatic;
  SamplerKind sampler = SamplerKind::sobol;
  uint64_t seed = 0;
  int threads = 0;     ///< 0 = all cores
  bool force_generic_kernel = false;  ///< benchmarks only: disable the specialization on scene features

  bool operator==(const RenderParams&) const = default;
};

}  // namespace pt
