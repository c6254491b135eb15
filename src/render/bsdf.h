#pragma once
/// The three materials' scattering: Lambertian diffuse, ideal mirror and smooth dielectric (pbrt-v4 sections 9.2,
/// 9.3 and 9.5). All directions are world space; `n` is the shading normal already turned to the side of `wo`, and
/// `ng_side` tells on which side of the geometric surface `wo` lies, so that a reflection never leaks through.
#include "core/frame.h"
#include "core/math.h"
#include "core/sampling.h"
#include "scene/scene.h"

namespace pt {

/// Unpolarized Fresnel reflectance of a smooth dielectric boundary. `cos_i` is the cosine of the incident angle on
/// the side the light comes from, `eta` = n_transmitted / n_incident. Returns 1 under total internal reflection.
inline float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, -1.0f, 1.0f);
  if (cos_i < 0.0f) {
    eta = 1.0f / eta;
    cos_i = -cos_i;
  }
  float sin2_i = 1.0f - cos_i * cos_i;
  float sin2_t = sin2_i / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  float cos_t = safe_sqrt(1.0f - sin2_t);
  float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

/// Mirror direction of `wo` about `n`.
inline vec3 reflect_dir(vec3 wo, vec3 n) { return 2.0f * glm::dot(wo, n) * n - wo; }

/// Refraction of `wo` (pointing away from the surface, on the side of `n`) into the other medium, with
/// eta = n_other / n_this (Snell's law). Returns false under total internal reflection.
inline bool refract_dir(vec3 wo, vec3 n, float eta, vec3& wt) {
  float cos_i = glm::dot(n, wo);
  float sin2_i = std::max(0.0f, 1.0f - cos_i * cos_i);
  float sin2_t = sin2_i / (eta * eta);
  if (sin2_t >= 1.0f) return false;
  float cos_t = safe_sqrt(1.0f - sin2_t);
  wt = -wo / eta + (cos_i / eta - cos_t) * n;
  return true;
}

/// The result of sampling a BSDF: the new direction and the path weight f * |cos| / pdf.
struct BsdfSample {
  vec3 wi{0.0f};
  vec3 weight{0.0f};
  float pdf = 0.0f;       ///< solid-angle density; for delta lobes the discrete probability of the lobe
  bool delta = false;     ///< specular: cannot be light-sampled, skip MIS
  float eta_scale = 1.0f; ///< factor the radiance was scaled by (1/eta^2 for a refraction), for Russian roulette
};

/// The local geometry a BSDF needs at a path vertex.
struct ShadingContext {
  vec3 wo;      ///< toward the previous vertex, unit
  vec3 n;       ///< shading normal on the side of wo, unit
  vec3 ng;      ///< geometric normal on the side of wo, unit
  bool entering = true;  ///< wo is on the outside (the geometric normal's front side); for glass
};

inline bool is_delta(const Material& m) { return info_of(m.type).delta; }

/// f(wo, wi) |cos theta_i| for a non-delta material (diffuse), 0 when wi is below the geometric surface.
inline vec3 eval_bsdf_cos(const Material& m, const ShadingContext& sc, vec3 wi) {
  if (m.type != MaterialType::diffuse) return vec3(0.0f);
  if (glm::dot(wi, sc.ng) <= 0.0f) return vec3(0.0f);
  return m.albedo * (kInvPi * std::max(0.0f, glm::dot(wi, sc.n)));
}

/// Solid-angle pdf of sample_bsdf producing wi (0 for delta materials).
inline float bsdf_pdf(const Material& m, const ShadingContext& sc, vec3 wi) {
  if (m.type != MaterialType::diffuse) return 0.0f;
  if (glm::dot(wi, sc.ng) <= 0.0f) return 0.0f;
  return cosine_hemisphere_pdf(glm::dot(wi, sc.n));
}

/// Cosine-weighted sampling of a diffuse BRDF: the whole of sample_bsdf for scenes without mirrors or glass.
inline bool sample_diffuse(const Material& m, const ShadingContext& sc, vec2 u, BsdfSample& out) {
  vec3 local = sample_cosine_hemisphere(u);
  vec3 wi = Frame::from_normal(sc.n).to_world(local);
  if (glm::dot(wi, sc.ng) <= 0.0f || local.z <= 0.0f) return false;
  out = {wi, m.albedo, cosine_hemisphere_pdf(local.z), false, 1.0f};
  return true;
}

/// Samples an incident direction. `u_lobe` picks reflection or refraction for glass, `u` drives the direction.
/// Returns false when the sample carries no energy.
bool sample_bsdf(const Material& m, const ShadingContext& sc, float u_lobe, vec2 u, BsdfSample& out);

}  // namespace pt
