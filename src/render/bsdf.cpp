#include "render/bsdf.h"

#include "core/sampling.h"

namespace pt {

bool sample_bsdf(const Material& m, const ShadingContext& sc, float u_lobe, vec2 u, BsdfSample& out) {
  switch (m.type) {
    case MaterialType::diffuse:
      return sample_diffuse(m, sc, u, out);
    case MaterialType::specular: {
      vec3 wi = reflect_dir(sc.wo, sc.n);
      if (glm::dot(wi, sc.ng) <= 0.0f) return false;
      out = {wi, m.albedo, 1.0f, true, 1.0f};
      return true;
    }
    case MaterialType::glass: {
      // eta = n_transmitted / n_incident for light travelling from the far side toward wo's side.
      float eta = sc.entering ? m.ior : 1.0f / m.ior;
      float cos_o = glm::dot(sc.wo, sc.n);
      float reflectance = fresnel_dielectric(cos_o, eta);
      vec3 wt;
      if (u_lobe < reflectance || !refract_dir(sc.wo, sc.n, eta, wt)) {
        vec3 wi = reflect_dir(sc.wo, sc.n);
        if (glm::dot(wi, sc.ng) <= 0.0f) return false;
        out = {wi, vec3(1.0f), reflectance, true, 1.0f};
        return true;
      }
      if (glm::dot(wt, sc.ng) >= 0.0f) return false;
      // Radiance is compressed by 1/eta^2 on entering a denser medium (pbrt-v4 section 9.5.2, non-symmetric
      // scattering); the weight T * (1/eta^2) / T leaves just the scale.
      float scale = 1.0f / (eta * eta);
      out = {wt, vec3(scale), 1.0f - reflectance, true, scale};
      return true;
    }
  }
  return false;
}

}  // namespace pt
