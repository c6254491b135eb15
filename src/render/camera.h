#pragma once
/// The pinhole camera exactly as the README specifies, so images can be compared with computed answers.
#include "core/ray.h"
#include "scene/scene.h"

namespace pt {

/// The camera's orthonormal frame and image-plane scale, computed once per render.
struct CameraRig {
  vec3 eye, forward, right, up;
  float tan_half_fov = 0.4f;
  float aspect = 1.0f;
  int width = 1, height = 1;
};

/// forward = normalize(target - eye), right = normalize(cross(forward, up)), up' = cross(right, forward).
inline CameraRig make_camera_rig(const Camera& cam, int width, int height) {
  CameraRig rig;
  rig.eye = cam.eye;
  rig.forward = glm::normalize(cam.target - cam.eye);
  rig.right = glm::normalize(glm::cross(rig.forward, cam.up));
  rig.up = glm::cross(rig.right, rig.forward);
  rig.tan_half_fov = std::tan(glm::radians(cam.fov_deg) * 0.5f);
  rig.width = width;
  rig.height = height;
  rig.aspect = float(width) / float(height);
  return rig;
}

/// The ray through pixel (i, j) (column from the left, row from the top) at offset (u, v) in [0,1)^2.
inline Ray generate_camera_ray(const CameraRig& rig, int i, int j, vec2 u) {
  float x = (2.0f * (float(i) + u.x) / float(rig.width) - 1.0f) * rig.tan_half_fov * rig.aspect;
  float y = (1.0f - 2.0f * (float(j) + u.y) / float(rig.height)) * rig.tan_half_fov;
  return Ray{rig.eye, glm::normalize(rig.forward + x * rig.right + y * rig.up), kInfinity};
}

}  // namespace pt
