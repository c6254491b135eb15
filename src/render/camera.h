#pragma once
/// The pinhole camera exactly as the README specifies, so images can be compared with computed answers.
#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "core/ray.h"
#include "scene/scene.h"

namespace pt {

/// The camera's orthonormal frame and image-plane scale, computed once per render. The README's
/// x = (2(i+u)/W - 1) tan(fov/2) W/H is kept as x = (i+u) x_step - x_half with x_step = 2 tan(fov/2) W/H / W and
/// x_half = tan(fov/2) W/H (y likewise): the same plane point to rounding, without the two divisions per camera ray
/// that were the start of every path's dependent chain (docs/BENCHMARKS.md, fourteenth round).
struct CameraRig {
  vec3 eye, forward, right, up;
  float x_step = 0.8f, x_half = 0.4f, y_step = 0.8f, y_half = 0.4f;
};

/// forward = normalize(target - eye), right = normalize(cross(forward, up)), up' = cross(right, forward).
inline CameraRig make_camera_rig(const Camera& cam, int width, int height) {
  CameraRig rig;
  rig.eye = cam.eye;
  rig.forward = glm::normalize(cam.target - cam.eye);
  rig.right = glm::normalize(glm::cross(rig.forward, cam.up));
  rig.up = glm::cross(rig.right, rig.forward);
  const float tan_half_fov = std::tan(glm::radians(cam.fov_deg) * 0.5f);
  const float aspect = float(width) / float(height);
  rig.x_half = tan_half_fov * aspect;
  rig.x_step = 2.0f * rig.x_half / float(width);
  rig.y_half = tan_half_fov;
  rig.y_step = 2.0f * rig.y_half / float(height);
  return rig;
}

/// 1 / sqrt(x) as the hardware estimate refined by one Newton step. The exact square root and division were the
/// longest part of a camera ray's latency, which every path waits on; the unit direction this gives is as close to
/// length 1 as glm::normalize's (within 2.3e-7 against 1.7e-7 over 2e7 random directions). The estimate's table is
/// the CPU vendor's, so the last bit of a direction may differ between vendors (images are bit-identical across
/// thread counts on one machine, as before).
inline float camera_rsqrt(float x) {
#if defined(__SSE__)
  const float r = _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(x)));
  return r * (1.5f - 0.5f * x * r * r);
#else
  return 1.0f / std::sqrt(x);
#endif
}

/// The ray through pixel (i, j) (column from the left, row from the top) at offset (u, v) in [0,1)^2.
inline Ray generate_camera_ray(const CameraRig& rig, int i, int j, vec2 u) {
  const float x = (float(i) + u.x) * rig.x_step - rig.x_half;
  const float y = rig.y_half - (float(j) + u.y) * rig.y_step;
  const vec3 d = rig.forward + x * rig.right + y * rig.up;
  return Ray{rig.eye, d * camera_rsqrt(glm::dot(d, d)), kInfinity};
}

}  // namespace pt
