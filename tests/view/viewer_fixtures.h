#pragma once
// Scenes and parameters shared by the viewer-state and panel tests: small renders that start at once.
#include <gtest/gtest.h>

#include <string_view>
#include <utility>

#include "render/render_params.h"
#include "scene/load.h"
#include "scene/scene.h"

namespace pt::test {

/// 32 x 24, depth 4, one thread: a render whose frames take a millisecond.
inline RenderParams small_params() {
  RenderParams p;
  p.width = 32;
  p.height = 24;
  p.max_depth = 4;
  p.threads = 1;
  return p;
}

/// A built-in scene by name (a failure to load fails the test).
inline Scene builtin(std::string_view name) {
  Result<Scene> s = load_builtin_scene(name);
  EXPECT_TRUE(s.ok()) << name;
  return std::move(*s);
}

/// A 4 x 4 floor under a sphere light of radius 0.2 at (0.5, 1.5, -0.25): no built-in scene has a sphere light.
inline Scene floor_under_a_sphere_light() {
  Scene s;
  Material floor, lamp;
  floor.name = "floor";
  lamp.name = "lamp";
  lamp.emission = vec3(2.0f);
  s.materials = {floor, lamp};
  s.quads.push_back({vec3(-2, 0, 2), vec3(4, 0, 0), vec3(0, 0, -4), 0});
  s.spheres.push_back({{vec3(0.5f, 1.5f, -0.25f), 0.2f}, 1});
  return s;
}

}  // namespace pt::test
