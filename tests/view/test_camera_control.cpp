// The mouse and keyboard camera motions (view/camera_control.h) against their geometry, written out here: the viewer
// tests compare the window with headless renders of the same motions, which a wrong motion passes.
#include <gtest/gtest.h>

#include "view/camera_control.h"

namespace pt {
namespace {

Camera test_camera() {
  Camera c;
  c.eye = vec3(1.0f, 2.0f, 5.0f);
  c.target = vec3(0.5f, 1.0f, -1.0f);
  c.up = vec3(0.0f, 1.0f, 0.0f);
  c.fov_deg = 50.0f;
  return c;
}

void expect_near(vec3 a, vec3 b, float tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

double elevation_deg(const Camera& c) {
  const dvec3 d = glm::normalize(dvec3(c.eye - c.target));
  return glm::degrees(std::asin(glm::dot(d, glm::normalize(dvec3(c.up)))));
}

TEST(CameraControl, PanMovesEyeAndTargetAlongTheImagePlaneByFractionsOfTheViewHeight) {
  const Camera before = test_camera();
  const vec3 forward = glm::normalize(before.target - before.eye);
  const vec3 right = glm::normalize(glm::cross(forward, before.up)), up = glm::cross(right, forward);
  const float dist = glm::length(before.target - before.eye);
  const float view_height = 2.0f * dist * std::tan(glm::radians(before.fov_deg) / 2.0f);
  Camera c = before;
  pan_camera(c, 0.1f, -0.25f);
  // Dragging right by a tenth of the view height moves the scene with the mouse: the camera goes left; dragging
  // up (negative y in window coordinates) moves it down.
  const vec3 expected = (-0.1f * right - 0.25f * up) * view_height;
  expect_near(c.eye - before.eye, expected, 1e-5f);
  expect_near(c.target - before.target, expected, 1e-5f);
  EXPECT_EQ(c.up, before.up);
  EXPECT_EQ(c.fov_deg, before.fov_deg);
}

TEST(CameraControl, DollyScalesTheDistanceAndKeepsTheDirection) {
  const Camera before = test_camera();
  Camera c = before;
  dolly_camera(c, 0.5f, 1e-4f);
  EXPECT_EQ(c.target, before.target);
  expect_near(c.eye - c.target, 0.5f * (before.eye - before.target), 1e-5f);
  // Never through the target, however many times the wheel turns: it stops at the floor.
  for (int i = 0; i < 200; ++i) dolly_camera(c, 0.5f, 1e-4f);
  EXPECT_NEAR(camera_distance(c), 1e-4f, 1e-6f);  // to the rounding of eye's coordinates (about 1)
  EXPECT_GT(glm::dot(c.eye - c.target, before.eye - before.target), 0.0f);
}

TEST(CameraControl, EveryMotionIsTheSameAtAnyScale) {
  // The same motions on the test camera scaled by s give the scaled result: no absolute length in the controls
  // (the dolly's floor scales with the scene, camera_min_distance), and no float square of a length that vanishes at
  // 1e-20 or overflows at 1e20.
  const float size = 10.0f;  // the scene the test camera looks at, in its own units
  auto moves = [&](Camera c, float s) {
    orbit_camera(c, 30.0f, -10.0f);
    pan_camera(c, 0.1f, -0.05f);
    for (int i = 0; i < 4; ++i) dolly_camera(c, 0.5f, camera_min_distance(size * s));
    fly_camera(c, s * vec3(0.5f, 0.25f, -1.0f));
    return c;
  };
  const Camera ref = moves(test_camera(), 1.0f);
  for (float s : {1e-20f, 1e-6f, 1e6f, 1e20f}) {
    Camera scaled = test_camera();
    scaled.eye *= s;
    scaled.target *= s;
    Camera c = moves(scaled, s);
    expect_near(c.eye / s, ref.eye, 1e-5f);
    expect_near(c.target / s, ref.target, 1e-5f);
    // The dolly stops at the same fraction of the scene.
    for (int i = 0; i < 200; ++i) dolly_camera(c, 0.5f, camera_min_distance(size * s));
    EXPECT_NEAR(camera_distance(c) / s, camera_min_distance(size), 1e-6f) << s;
  }
}

TEST(CameraControl, FlyMovesAlongTheCamerasOwnAxes) {
  const Camera before = test_camera();
  const vec3 forward = glm::normalize(before.target - before.eye);
  const vec3 right = glm::normalize(glm::cross(forward, before.up)), up = glm::cross(right, forward);
  Camera c = before;
  fly_camera(c, vec3(0.3f, -0.2f, 1.5f));  // right, up, forward
  const vec3 expected = 0.3f * right - 0.2f * up + 1.5f * forward;
  expect_near(c.eye - before.eye, expected, 1e-5f);
  expect_near(c.target - before.target, expected, 1e-5f);
}

TEST(CameraControl, OrbitStopsShortOfThePolesWithoutFlippingOver) {
  for (float pitch : {200.0f, -200.0f, 100.0f, -100.0f}) {  // from 9.4 degrees of elevation
    const Camera before = test_camera();
    Camera c = before;
    orbit_camera(c, 0.0f, pitch);
    EXPECT_EQ(c.target, before.target);
    EXPECT_NEAR(glm::length(c.eye - c.target), glm::length(before.eye - before.target), 1e-4f);
    EXPECT_NEAR(elevation_deg(c), pitch > 0 ? 89.0 : -89.0, 1e-3) << "pitch " << pitch;
    // Still on the same side of the target: the horizontal direction to the eye has not turned around.
    const vec3 h0 = before.eye - before.target, h1 = c.eye - c.target;
    EXPECT_GT(h0.x * h1.x + h0.z * h1.z, 0.0f) << "pitch " << pitch;
    // And the pole is a wall, not a trap: pitching back comes away from it.
    orbit_camera(c, 0.0f, pitch > 0 ? -30.0f : 30.0f);
    EXPECT_NEAR(elevation_deg(c), pitch > 0 ? 59.0 : -59.0, 1e-2) << "pitch " << pitch;
  }
}

}  // namespace
}  // namespace pt
