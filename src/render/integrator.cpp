#include "render/integrator.h"

#include "render/bsdf.h"

namespace pt {

namespace {

/// How a non-delta vertex samples lights: the requested mode and, for automatic, the area-density spread from which
/// a rectangle is sampled by solid angle (light.h, kAutoMinSpread). The first non-delta vertex of a path (the
/// surface the camera sees, directly or through mirrors and glass) takes the scene's choice,
/// RenderScene::auto_first_spread (kAutoMinSpread where the pilot of render/auto_light_sampling.h finds that it
/// pays, else kAutoMinSpreadDeep); deeper vertices ask for the larger spread. Why: the first vertex's direct light
/// reaches the image unattenuated, so where it is much of the image the lower variance of solid-angle sampling
/// shows; deeper vertices are weighted by a path throughput whose own variance hides most of the difference, and
/// there the cheaper area sampling wins per second except close to a light (bench-error, issue 11). The choice
/// depends only on the scene and the path so far, and light_pdf is asked with the same one: unbiased.
struct VertexLightSampling {
  LightSampling mode = LightSampling::area;
  float min_spread = kAutoMinSpread;

  static VertexLightSampling at(LightSampling requested, bool first_non_delta, float first_spread) {
    return {requested, first_non_delta ? first_spread : kAutoMinSpreadDeep};
  }
};

/// The state carried from one path vertex to the next for MIS of a later emitter hit.
struct PrevVertex {
  vec3 p{0.0f};
  float bsdf_pdf = 0.0f;
  bool delta = true;  ///< the camera counts as a delta "bounce": emission seen directly is always added
  VertexLightSampling light_sampling;  ///< how that vertex sampled lights, for light_pdf
};

/// The random numbers one path vertex consumes, drawn together so every vertex uses the same sampler dimensions
/// whatever branch it takes (this keeps low-discrepancy dimensions aligned across a pixel's samples). Two 4D
/// draws: what light sampling needs, and what BSDF sampling needs, each with its 2D point in the two best
/// stratified dimensions (Cycles groups them the same way).
struct VertexSamples {
  float light_choice;
  vec2 light_point;
  float lobe;
  vec2 direction;
  float roulette;

  static VertexSamples draw(PixelSampler& s) {
    float a[4], b[3];
    s.next<4>(a);
    s.next<3>(b);
    VertexSamples v;
    v.light_point = {a[0], a[1]};
    v.light_choice = a[2];
    v.roulette = a[3];
    v.direction = {b[0], b[1]};
    v.lobe = b[2];
    return v;
  }
};

vec3 direct_light(const RenderScene& scene, const RenderParams& params, VertexLightSampling mode, const SurfaceHit& sh,
                  const ShadingContext& sc, const Material& m, const VertexSamples& vs, RenderCounters& c) {
  if (sh.unlit_sides & (sc.entering ? 1 : 2)) {
    // Every light lies below this side's plane: eval_bsdf_cos would be zero toward any sample (render_scene.h,
    // tri_unlit_sides). The numbers in vs are drawn already, so skipping changes no later sample.
    ++c.shadow_skipped_zero_bsdf;
    return vec3(0.0f);
  }
  const float u_light = vs.light_choice;
  const vec2 u = vs.light_point;
  float pmf = 0.0f;
  size_t li = scene.lights.power.sample(u_light, &pmf);
  const Light& light = scene.lights.lights[li];
  LightSample ls;
  if (!sample_light(light, sh.sp.p, u, mode.mode, ls, mode.min_spread) || !(ls.pdf > 0.0f)) {
    ++c.shadow_skipped_backfacing;
    return vec3(0.0f);
  }
  vec3 f = eval_bsdf_cos(m, sc, ls.wi);
  if (is_black(f)) {
    ++c.shadow_skipped_zero_bsdf;
    return vec3(0.0f);
  }
  ++c.shadow_rays;
  if (intersect_any(scene.trace(), spawn_ray_to(sh.sp, ls.point))) return vec3(0.0f);
  float light_pdf_total = pmf * ls.pdf;
  float weight = 1.0f;
  if (params.integrator == IntegratorKind::mis) weight = power_heuristic(light_pdf_total, bsdf_pdf(m, sc, ls.wi));
  return f * ls.radiance * (weight / light_pdf_total);
}

}  // namespace

/// The path loop, specialized on scene features (pbrt-v4 and Embree habit: decide once, not per ray): without
/// mirrors or glass every vertex is diffuse, so the delta-BSDF branches are not compiled in; without a background
/// escaping paths add nothing.
template <bool kDelta, bool kBackground>
vec3 trace_path_impl(const RenderScene& scene, const RenderParams& params, float first_spread, vec3 org, vec3 dir,
                     float tmax, PixelSampler& sampler, RenderCounters& c) {
  Ray ray{org, dir, tmax};
  vec3 radiance(0.0f);
  vec3 beta(1.0f);
  float eta_scale = 1.0f;
  PrevVertex prev;
  bool first_non_delta = true;
  const bool sample_lights = params.integrator != IntegratorKind::bsdf && !scene.lights.empty();
  ++c.camera_rays;
  for (int depth = 0;; ++depth) {
    Hit hit;
    if (!intersect_closest(scene.trace(), ray, hit)) {
      // The background is never light-sampled, so BSDF sampling always counts it in full.
      if constexpr (kBackground) radiance += beta * scene.background;
      ++c.paths_escaped;
      break;
    }
    SurfaceHit sh = make_surface_hit(scene, ray, hit);
    const Material& m = scene.materials[sh.material];
    vec3 wo = -ray.dir;
    bool front = glm::dot(wo, sh.sp.ng) > 0.0f;

    if (front && m.emissive()) {
      if (prev.delta || params.integrator == IntegratorKind::bsdf || sh.light < 0) {
        radiance += beta * m.emission;
      } else if (params.integrator == IntegratorKind::mis) {
        const Light& light = scene.lights.lights[size_t(sh.light)];
        float lpdf = scene.lights.power.pmf(size_t(sh.light)) *
                     light_pdf(light, prev.p, ray.dir, hit.t, sh.sp.ng, prev.light_sampling.mode,
                               prev.light_sampling.min_spread);
        radiance += beta * m.emission * power_heuristic(prev.bsdf_pdf, lpdf);
      }
      // nee: this emitter was already counted by light sampling at the previous vertex.
    }
    if (depth == params.max_depth) {
      ++c.paths_ended_max_depth;
      break;
    }

    ShadingContext sc;
    sc.wo = wo;
    sc.entering = front;
    // A sign factor rather than a choice between two vectors: the choice compiled to 8- and 4-byte copies through
    // the stack whose reload as a pair stalled store forwarding (10% of the path loop's own time in perf). Exact:
    // multiplying by +-1 only flips signs.
    const float side = front ? 1.0f : -1.0f;
    sc.ng = side * sh.sp.ng;
    sc.n = side * sh.ns;

    const VertexSamples vs = VertexSamples::draw(sampler);
    const bool delta_vertex = kDelta && is_delta(m);
    const VertexLightSampling mode = VertexLightSampling::at(params.light_sampling, first_non_delta, first_spread);
    if (!delta_vertex) first_non_delta = false;
    if (sample_lights) {
      if (delta_vertex) ++c.light_sampling_skipped_specular;
      else radiance += beta * direct_light(scene, params, mode, sh, sc, m, vs, c);
    }

    BsdfSample bs;
    bool sampled;
    if constexpr (kDelta)
      sampled = sample_bsdf(m, sc, vs.lobe, vs.direction, bs);
    else
      sampled = sample_diffuse(m, sc, vs.direction, bs);
    if (!sampled) {
      ++c.paths_ended_absorbed;
      break;
    }
    beta *= bs.weight;
    eta_scale *= bs.eta_scale;
    prev = {sh.sp.p, bs.pdf, bs.delta, mode};
    ray = spawn_ray(sh.sp, bs.wi);

    // Russian roulette on the throughput with the eta^2 scaling undone (pbrt-v4 section 13.4.4). Without glass
    // eta_scale stays exactly 1, and the division, on the loop's critical path, is skipped.
    const float rr_max = kDelta ? max_component(beta / eta_scale) : max_component(beta);
    if (!(rr_max > 0.0f)) {
      ++c.paths_ended_absorbed;
      break;
    }
    if (depth >= 2) {
      const float survive = roulette_survival(rr_max);
      if (survive < 1.0f) {
        if (vs.roulette >= survive) {
          ++c.paths_ended_roulette;
          break;
        }
        beta *= 1.0f / survive;  // one division rather than one per channel
      }
    }
    ++c.bounce_rays;  // counted here, where it is sure to be traced: not for a path that roulette just ended
  }
  return radiance;
}

IntegratorKind resolve_integrator(IntegratorKind kind, LightSampling light_sampling) {
  if (kind != IntegratorKind::automatic) return kind;
  return light_sampling == LightSampling::area ? IntegratorKind::mis : IntegratorKind::nee;
}

vec3 trace_path(const RenderScene& scene, const RenderParams& params_in, float first_spread, vec3 org, vec3 dir,
                float tmax, PixelSampler& sampler, RenderCounters& c) {
  RenderParams params = params_in;
  params.integrator = resolve_integrator(params.integrator, params.light_sampling);
  const bool delta = scene.features.has_delta || params.force_generic_kernel;
  const bool background = scene.features.has_background || params.force_generic_kernel;
  if (delta) {
    return background ? trace_path_impl<true, true>(scene, params, first_spread, org, dir, tmax, sampler, c)
                      : trace_path_impl<true, false>(scene, params, first_spread, org, dir, tmax, sampler, c);
  }
  return background ? trace_path_impl<false, true>(scene, params, first_spread, org, dir, tmax, sampler, c)
                    : trace_path_impl<false, false>(scene, params, first_spread, org, dir, tmax, sampler, c);
}

const char* kernel_name(const RenderScene& scene, const RenderParams& params) {
  if (params.force_generic_kernel) return "generic";
  bool delta = scene.features.has_delta;
  if (delta) return scene.features.has_background ? "all-materials+background" : "all-materials";
  return scene.features.has_background ? "diffuse-only+background" : "diffuse-only";
}

}  // namespace pt
