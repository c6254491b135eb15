#pragma once
/// Mouse and keyboard camera motions on a pt::Camera: orbit around the target, pan, dolly, fly.
#include "scene/scene.h"

namespace pt {

/// Orbits the eye around the target: `yaw_deg` about the camera's up axis, `pitch_deg` about its right axis,
/// never flipping over the poles.
inline void orbit_camera(Camera& cam, float yaw_deg, float pitch_deg) {
  vec3 up = glm::normalize(cam.up);
  vec3 offset = cam.eye - cam.target;
  float dist = glm::length(offset);
  if (!(dist > 0.0f)) return;
  vec3 dir = offset / dist;
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
  vec3 forward = cam.target - cam.eye;
  float dist = glm::length(forward);
  if (!(dist > 0.0f)) return;
  forward /= dist;
  vec3 right = glm::normalize(glm::cross(forward, cam.up));
  vec3 up = glm::cross(right, forward);
  float scale = 2.0f * dist * std::tan(glm::radians(cam.fov_deg) * 0.5f);
  vec3 delta = (-dx * right + dy * up) * scale;
  cam.eye += delta;
  cam.target += delta;
}

/// Scales the eye's distance to the target by `factor` (< 1 moves closer).
inline void dolly_camera(Camera& cam, float factor) {
  vec3 offset = cam.eye - cam.target;
  float dist = glm::length(offset);
  float new_dist = std::max(dist * factor, 1e-4f);
  if (dist > 0.0f) cam.eye = cam.target + offset * (new_dist / dist);
}

/// Moves eye and target along the camera's own axes (WASD/QE flying).
inline void fly_camera(Camera& cam, vec3 local_move) {
  vec3 forward = glm::normalize(cam.target - cam.eye);
  vec3 right = glm::normalize(glm::cross(forward, cam.up));
  vec3 up = glm::cross(right, forward);
  vec3 delta = local_move.x * right + local_move.y * up + local_move.z * forward;
  cam.eye += delta;
  cam.target += delta;
}

}  // namespace pt
