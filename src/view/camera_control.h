#pragma once
/// Mouse and keyboard camera motions on a pt::Camera: orbit around the target, pan, dolly, fly. Distances are taken
/// in double and no motion has an absolute length in it, so the controls behave the same for a scene 1e-15 or 1e15
/// across (float squares of lengths vanish or overflow there).
#include "render/render_scene.h"
#include "scene/scene.h"

namespace pt {

/// |eye - target|, without float's overflow or underflow of its square.
inline float camera_distance(const Camera& cam) { return float(glm::length(dvec3(cam.eye) - dvec3(cam.target))); }

/// Orbits the eye around the target: `yaw_deg` about the camera's up axis, `pitch_deg` about its right axis,
/// never flipping over the poles.
inline void orbit_camera(Camera& cam, float yaw_deg, float pitch_deg) {
  vec3 up = glm::normalize(cam.up);
  const float dist = camera_distance(cam);
  if (!(dist > 0.0f) || !std::isfinite(dist)) return;
  vec3 dir = (cam.eye - cam.target) / dist;
  // Rotate about up (yaw).
  float yaw = glm::radians(yaw_deg);
  dir = std::cos(yaw) * dir + std::sin(yaw) * glm::cross(up, dir) + (1.0f - std::cos(yaw)) * glm::dot(up, dir) * up;
  // Pitch, clamped away from the poles.
  float elevation = std::asin(std::clamp(glm::dot(dir, up), -1.0f, 1.0f));
  float target_elev = std::clamp(elevation + glm::radians(pitch_deg), glm::radians(-89.0f), glm::radians(89.0f));
  vec3 horizontal = dir - glm::dot(dir, up) * up;
  float hl = glm::length(horizontal);
  if (hl < 1e-6f) return;
  horizontal /= hl;
  dir = std::cos(target_elev) * horizontal + std::sin(target_elev) * up;
  cam.eye = cam.target + dist * dir;
}

/// Moves eye and target together along the image plane; `dx`, `dy` in fractions of the view height.
inline void pan_camera(Camera& cam, float dx, float dy) {
  const float dist = camera_distance(cam);
  if (!(dist > 0.0f) || !std::isfinite(dist)) return;
  const vec3 forward = (cam.target - cam.eye) / dist;
  vec3 right = glm::normalize(glm::cross(forward, cam.up));
  vec3 up = glm::cross(right, forward);
  float scale = 2.0f * dist * std::tan(glm::radians(cam.fov_deg) * 0.5f);
  vec3 delta = (-dx * right + dy * up) * scale;
  cam.eye += delta;
  cam.target += delta;
}

/// Scales the eye's distance to the target by `factor` (< 1 moves closer), down to `min_distance` (callers pass a
/// small fraction of the scene's size, camera_min_distance) and never within float rounding of the target.
inline void dolly_camera(Camera& cam, float factor, float min_distance) {
  const float dist = camera_distance(cam);
  if (!(dist > 0.0f) || !std::isfinite(dist)) return;
  const float new_dist = std::max({dist * factor, min_distance, 1e-6f * max_component(glm::abs(cam.target))});
  cam.eye = cam.target + (cam.eye - cam.target) * (new_dist / dist);
}

/// The size of the scene `g` was built from, in world units (the diagonal of its bounds); 0 without geometry.
inline float scene_size(const RenderGeometry* g) {
  if (!g || g->trace.bounds().empty()) return 0.0f;
  return float(glm::length(dvec3(g->trace.bounds().extent())) / double(g->scale));
}

/// The viewer's unit of length: the scene's size, or 1 without geometry. Drag speeds, limits, the dolly's floor and
/// the fly speed are fractions of it, so the controls act the same on a scene 1e-6 or 1e6 across.
inline float scene_unit(const RenderGeometry* g) {
  const float s = scene_size(g);
  return s > 0.0f && std::isfinite(s) ? s : 1.0f;
}

/// The dolly's floor and the fly speed's for a scene `unit` across (scene_unit): a fixed fraction of it.
inline float camera_min_distance(float unit) { return 1e-5f * unit; }
inline float camera_min_distance(const RenderGeometry* g) { return camera_min_distance(scene_unit(g)); }

/// Moves eye and target along the camera's own axes (WASD/QE flying).
inline void fly_camera(Camera& cam, vec3 local_move) {
  const vec3 forward = vec3(glm::normalize(dvec3(cam.target) - dvec3(cam.eye)));
  vec3 right = glm::normalize(glm::cross(forward, cam.up));
  vec3 up = glm::cross(right, forward);
  vec3 delta = local_move.x * right + local_move.y * up + local_move.z * forward;
  cam.eye += delta;
  cam.target += delta;
}

}  // namespace pt
