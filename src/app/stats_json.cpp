#include <nlohmann/json.hpp>

#include "app/app.h"
#include "render/trace_stats_json.h"

namespace pt {

namespace {
const char* integrator_name(IntegratorKind k) {
  switch (k) {
    case IntegratorKind::mis: return "mis";
    case IntegratorKind::nee: return "nee";
    case IntegratorKind::bsdf: return "bsdf";
    case IntegratorKind::automatic: return "auto";
  }
  return "?";
}
}  // namespace

std::string make_stats_json(const AppOptions& options, const Scene& scene, const RenderScene& rs,
                            const RunSummary& run) {
  const RenderCounters& c = run.counters;
  double rays = double(c.rays());
  nlohmann::json j;
  j["scene"] = scene.source;
  j["width"] = options.render.width;
  j["height"] = options.render.height;
  j["frames"] = run.frames;
  j["spp"] = run.spp;
  j["seconds"] = run.seconds;
  j["spp_per_s"] = run.seconds > 0 ? run.spp / run.seconds : 0.0;
  j["rays"] = c.rays();
  j["mrays_per_s"] = run.seconds > 0 ? rays / run.seconds * 1e-6 : 0.0;
  j["samples"] = c.samples;
  j["nonfinite_samples"] = c.nonfinite_samples;
  j["threads"] = run.threads;
  j["integrator"] = integrator_name(options.render.integrator);
  j["light_sampling"] = options.render.light_sampling == LightSampling::area ? "area" : "solid-angle";
  j["sampler"] = options.render.sampler == SamplerKind::sobol ? "sobol" : "independent";
  j["max_depth"] = options.render.max_depth;
  j["seed"] = options.render.seed;
  j["load_ms"] = run.load_ms;
  j["triangles"] = rs.triangle_count();
  j["spheres"] = rs.geo->spheres.size();
  j["lights"] = rs.lights.lights.size();
  j["rays_by_kind"] = {{"camera", c.camera_rays}, {"bounce", c.bounce_rays}, {"shadow", c.shadow_rays}};
  j["bvh"] = trace_stats_json(rs.trace());
  j["skipped"] = nlohmann::json::object();
  for (const auto& [name, count] : skipped_work(c)) j["skipped"][name] = count;
  j["kernel"] = kernel_name(rs, options.render);
  j["features"] = {{"glass", rs.features.has_glass},
                   {"specular", rs.features.has_specular},
                   {"background", rs.features.has_background}};
  j["warnings"] = scene.warnings;
  return j.dump(2) + "\n";
}

ImageError compare_images(const Image& image, const Image& reference) {
  ImageError e;
  size_t n = image.rgb.size();
  if (n == 0 || n != reference.rgb.size()) return e;
  double se = 0.0, rel = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double r = reference.rgb[i];
    double d = double(image.rgb[i]) - r;
    se += d * d;
    rel += d * d / (r * r + 0.01);
  }
  e.rmse = std::sqrt(se / double(n));
  e.rel_mse = rel / double(n);
  return e;
}

}  // namespace pt
