#include "render/stats_json.h"

#include <algorithm>

#include "render/auto_light_sampling.h"
#include "render/integrator.h"
#include "render/names.h"
#include "render/trace_stats_json.h"

namespace pt {

nlohmann::json make_stats_json(const RenderParams& params, const Scene& scene, const RenderScene& rs,
                               const RunSummary& run) {
  const RenderCounters& c = run.counters;
  double rays = double(c.rays());
  nlohmann::json j;
  j["scene"] = scene.source;
  j["width"] = params.width;
  j["height"] = params.height;
  j["frames"] = run.frames;
  j["spp"] = run.spp;
  j["seconds"] = run.seconds;
  j["spp_per_s"] = run.seconds > 0 ? run.spp / run.seconds : 0.0;
  j["rays"] = c.rays();
  j["mrays_per_s"] = run.seconds > 0 ? rays / run.seconds * 1e-6 : 0.0;
  j["samples"] = c.samples;
  j["nonfinite_samples"] = c.nonfinite_samples;
  j["threads"] = run.threads;
  j["epoch"] = run.epoch;
  j["ranks"] = std::max<size_t>(1, run.per_rank.size());
  j["per_rank"] = nlohmann::json::array();
  for (const RankWork& w : run.per_rank) j["per_rank"].push_back({{"spp", w.spp}, {"seconds", w.seconds}});
  j["comm_ms"] = run.comm_ms;
  j["integrator"] = name_of(params.integrator);
  j["light_sampling"] = name_of(params.light_sampling);
  j["sampler"] = name_of(params.sampler);
  j["max_depth"] = params.max_depth;
  j["seed"] = params.seed;
  j["load_ms"] = run.load_ms;
  j["triangles"] = rs.triangle_count();
  j["spheres"] = rs.geo->spheres.size();
  j["lights"] = rs.lights.lights.size();
  // LightSampling::automatic's choice for this scene and camera (render/auto_light_sampling.h); a viewer's scene
  // may have left its pilot to the render session.
  const AutoLightSamplingChoice choice =
      rs.auto_pilot_pending ? choose_auto_light_sampling(rs)
                            : AutoLightSamplingChoice{rs.auto_first_spread, rs.auto_pilot_gain};
  j["auto_first_vertex"] = {{"min_spread", choice.first_spread},
                            {"pilot_gain", std::isfinite(choice.gain) ? nlohmann::json(choice.gain)
                                                                      : nlohmann::json(nullptr)}};
  j["rays_by_kind"] = {{"camera", c.camera_rays}, {"bounce", c.bounce_rays}, {"shadow", c.shadow_rays}};
  j["bvh"] = trace_stats_json(rs.trace());
  j["skipped"] = nlohmann::json::object();
  for (const auto& [name, count] : skipped_work(c)) j["skipped"][name] = count;
  j["kernel"] = kernel_name(rs, params);
  j["features"] = nlohmann::json::object();
  for (const EnumName<MaterialType>& t : kMaterialTypeNames)
    j["features"][t.name] = (rs.features.material_types >> unsigned(t.value) & 1u) != 0;
  j["features"]["background"] = rs.features.has_background;
  j["warnings"] = scene.warnings;
  const ConvergenceSummary& cv = run.convergence;
  j["est_rel_mse"] = std::isfinite(cv.est_rel_mse) ? nlohmann::json(cv.est_rel_mse) : nlohmann::json(nullptr);
  j["converged_fraction"] = cv.converged_fraction;
  j["spp_min"] = cv.spp.min;
  j["spp_max"] = cv.spp.max;
  j["spp_mean"] = cv.spp.mean;
  if (cv.noise_threshold > 0.0) {
    j["noise_threshold"] = cv.noise_threshold;
    j["min_spp"] = cv.min_spp;
  }
  return j;
}

ConvergenceSummary summarize_convergence(const ProgressiveFilm& film) {
  ConvergenceSummary c;
  c.est_rel_mse = est_rel_mse(film.film());
  c.converged_fraction = film.converged_fraction();
  c.spp = spp_summary(film.film());
  if (film.adaptive().enabled()) {
    c.noise_threshold = film.adaptive().noise_threshold;
    c.min_spp = effective_min_spp(film.adaptive());
  }
  return c;
}

}  // namespace pt
