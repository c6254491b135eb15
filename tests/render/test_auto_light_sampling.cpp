// LightSampling::automatic's per-scene choice (render/auto_light_sampling.h): the pilot takes solid angle at the
// first vertex where direct light is the image, area where indirect light dominates, looks through the camera, and
// is deterministic. Its unbiasedness under both choices is PolygonIrradiance's (test_integrator.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/auto_light_sampling.h"
#include "scene/load.h"
#include "scene_builders.h"

namespace pt {
namespace {

using test::add_material;
using test::diffuse;

/// bench-error's rect-light-over-plane: a 40 x 40 diffuse floor, a 1 x 1 light 0.8 above it facing down, the camera
/// looking down at the lit floor from nearby. All light is direct: the floor cannot light itself.
Scene lit_plane(Camera camera = Camera{vec3(0, 2.5f, 3.0f), vec3(0, 0, 0), vec3(0, 1, 0), 45.0f}) {
  Scene s;
  add_material(s, diffuse(vec3(0.5f)));
  const uint32_t light = add_material(s, diffuse(vec3(0.0f), vec3(5.0f)));
  s.quads.push_back({vec3(-20, 0, 20), vec3(40, 0, 0), vec3(0, 0, -40), 0});
  s.quads.push_back({vec3(-0.5f, 0.8f, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1), light});  // cross = -y: faces down
  s.camera = camera;
  return s;
}

TEST(AutoLightSampling, DirectLightOnlyTakesSolidAngleAtTheFirstVertex) {
  const RenderScene rs = make_render_scene(lit_plane());
  EXPECT_GT(rs.auto_pilot_gain, 0.5f) << "solid angle removes most of the lit plane's variance";
  EXPECT_EQ(rs.auto_first_spread, kAutoMinSpread);
}

TEST(AutoLightSampling, IndirectLightDominatedTakesAreaAtTheFirstVertex) {
  for (const char* name : {"cornell", "cornell-glass"}) {
    Result<Scene> s = load_builtin_scene(name);
    ASSERT_TRUE(s.ok()) << name;
    const RenderScene rs = make_render_scene(*s);
    EXPECT_LT(rs.auto_pilot_gain, kAutoMinGain) << name;
    EXPECT_GE(rs.auto_pilot_gain, -kAutoMinGain) << name << ": an estimate of a share of variance";
    EXPECT_EQ(rs.auto_first_spread, kAutoMinSpreadDeep) << name;
  }
}

TEST(AutoLightSampling, TheChoiceLooksThroughTheCamera) {
  // The same scene seen from below the floor (its back faces, black, and nothing else): nothing varies, nothing to
  // gain, so the cheaper sampling.
  const Camera below{vec3(0, -3, 0), vec3(0, -4, 0.1f), vec3(0, 1, 0), 45.0f};
  const RenderScene away = make_render_scene(lit_plane(below));
  EXPECT_EQ(away.auto_pilot_gain, 0.0f);
  EXPECT_EQ(away.auto_first_spread, kAutoMinSpreadDeep);
  // update_auto_light_sampling after a camera change gives what a fresh scene with that camera gives.
  RenderScene moved = away;
  moved.camera = make_render_scene(lit_plane()).camera;
  update_auto_light_sampling(moved);
  EXPECT_EQ(moved.auto_first_spread, kAutoMinSpread);
}

TEST(AutoLightSampling, DeterministicForAGivenSceneAndCamera) {
  const Scene s = lit_plane();
  const AutoLightSamplingChoice a = choose_auto_light_sampling(make_render_scene(s));
  const AutoLightSamplingChoice b = choose_auto_light_sampling(make_render_scene(s));
  EXPECT_EQ(a.gain, b.gain);
  EXPECT_EQ(a.first_spread, b.first_spread);
}

TEST(AutoLightSampling, BothPilotRunsDrawTheSameNumbers) {
  // The runs differ only in the first vertex's light sample (common random numbers), so a light too small and far
  // for either threshold to take solid angle gives both runs the same paths: no gain, exactly, not noise about it.
  Scene s = lit_plane();
  s.quads.back() = {vec3(-0.02f, 30.0f, -0.02f), vec3(0.04f, 0, 0), vec3(0, 0, 0.04f), 1};
  s.materials[1].emission = vec3(1e5f);
  const AutoLightSamplingChoice c = choose_auto_light_sampling(make_render_scene(s));
  EXPECT_EQ(c.gain, 0.0f);
}

TEST(AutoLightSampling, ANonFinitePathDoesNotSpoilTheChoice) {
  // A pixel whose paths reach an infinite emitter: its samples are left out, as the film drops them (render/film.h),
  // and the other pixels still find solid angle's gain on the lit plane.
  Scene s = lit_plane();
  const uint32_t hot = add_material(s, diffuse(vec3(0.5f), vec3(std::numeric_limits<float>::infinity())));
  s.spheres.push_back({vec3(0.4f, 0.05f, 0.4f), 0.05f, hot});
  const RenderScene rs = make_render_scene(s);
  EXPECT_GT(rs.auto_pilot_gain, 0.5f);
  EXPECT_EQ(rs.auto_first_spread, kAutoMinSpread);
}

TEST(AutoLightSampling, ScenesWithoutPlanarLightsAreNotMeasured) {
  Scene s = lit_plane();
  s.quads.pop_back();  // no light at all
  RenderScene none = make_render_scene(s);
  EXPECT_TRUE(std::isnan(none.auto_pilot_gain));
  EXPECT_EQ(none.auto_first_spread, kAutoMinSpread);
  s.spheres.push_back({vec3(0, 1, 0), 0.2f, 1});  // a sphere light: cone sampling whatever the threshold
  RenderScene sphere = make_render_scene(s);
  ASSERT_EQ(sphere.lights.lights.size(), 1u);
  EXPECT_TRUE(std::isnan(sphere.auto_pilot_gain));
}

}  // namespace
}  // namespace pt
