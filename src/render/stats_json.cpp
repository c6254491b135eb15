#include "render/stats_json.h"

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
  j["integrator"] = name_of(params.integrator);
  j["light_sampling"] = name_of(params.light_sampling);
  j["sampler"] = name_of(params.sampler);
  j["max_depth"] = params.max_depth;
  j["seed"] = params.seed;
  j["load_ms"] = run.load_ms;
  j["triangles"] = rs.triangle_count();
  j["spheres"] = rs.geo->spheres.size();
  j["lights"] = rs.lights.lights.size();
  j["rays_by_kind"] = {{"camera", c.camera_rays}, {"bounce", c.bounce_rays}, {"shadow", c.shadow_rays}};
  j["bvh"] = trace_stats_json(rs.trace());
  j["skipped"] = nlohmann::json::object();
  for (const auto& [name, count] : skipped_work(c)) j["skipped"][name] = count;
  j["kernel"] = kernel_name(rs, params);
  j["features"] = {{"glass", rs.features.has_glass},
                   {"specular", rs.features.has_specular},
                   {"background", rs.features.has_background}};
  j["warnings"] = scene.warnings;
  return j;
}

}  // namespace pt
