// The viewer's edit path without a window: which restart tier every kind of Edit takes, what it costs (BVH builds
// and refits counted), the preview frame after a restart, the old scene staying live during a load, the light
// model (which lights, their placement, resizing), and parse_script on every malformed form.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "fifo_watchdog.h"
#include "render/auto_light_sampling.h"
#include "scene/builtin_assets.h"
#include "scene/load.h"
#include "view/display_mode.h"
#include "view/script.h"
#include "view/viewer_state.h"
#include "temp_dir.h"
#include "viewer_fixtures.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

using test::builtin;
using test::floor_under_a_sphere_light;
using test::small_params;

/// A 1 x 1 x 1 room (floor and ceiling) whose ceiling light is two emissive triangles sharing two ceiling vertices,
/// like the public Cornell box OBJ: the light is 0.4 (x) by 0.2 (z) about (0.5, 1, 0.5).
std::string write_two_triangle_light_obj(const fs::path& dir) {
  std::ofstream(dir / "room.mtl") << "newmtl white\nKd 0.7 0.7 0.7\nnewmtl light\nKd 0.5 0.5 0.5\nKe 10 10 10\n";
  std::ofstream obj(dir / "room.obj");
  obj << "mtllib room.mtl\n"
         "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"              // 1-4 floor
         "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\n"              // 5-8 ceiling corners
         "v 0.3 1 0.4\nv 0.7 1 0.4\nv 0.7 1 0.6\nv 0.3 1 0.6\n"  // 9-12 light corners
         "usemtl white\nf 1 3 2\nf 1 4 3\nf 5 6 10\nf 5 10 9\n"   // floor; a ceiling strip sharing light vertices
         "usemtl light\nf 9 10 11\nf 9 11 12\n";                  // facing down
  return (dir / "room.obj").string();
}

using test::TempDir;

TEST(Tiers, EveryEditKindTakesItsTierAndCostsWhatItShould) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, -1);
  ASSERT_EQ(st.geometry_builds, 1);
  const int restarts0 = st.restarts;
  auto geo0 = st.geo;

  DisplaySettings d;
  d.exposure = 1.5f;
  EXPECT_EQ(st.apply(DisplayEdit{d}), Tier::display);
  EXPECT_EQ(st.restarts, restarts0) << "a display edit must not restart";
  EXPECT_EQ(st.display.exposure, 1.5f);

  Camera cam = *st.scene.camera;
  cam.eye.x += 0.3f;
  auto rs_before = st.render_scene;
  EXPECT_EQ(st.apply(CameraEdit{cam}), Tier::camera);
  EXPECT_EQ(st.restarts, restarts0 + 1);
  EXPECT_EQ(st.geo, geo0) << "a camera edit keeps the geometry";
  EXPECT_NE(st.render_scene, rs_before);
  EXPECT_FLOAT_EQ(st.render_scene->camera.eye.x + st.geo->origin.x, cam.eye.x);
  // The pilot of automatic light sampling looks through the camera (render/auto_light_sampling.h): the edit leaves
  // it to the render session (not the UI thread), which then chooses as the offload hosts, making the scene afresh,
  // do.
  EXPECT_TRUE(st.render_scene->auto_pilot_pending);
  const RenderScene fresh = make_render_scene(st.scene, st.geo);
  EXPECT_FALSE(fresh.auto_pilot_pending);
  const AutoLightSamplingChoice piloted = choose_auto_light_sampling(*st.render_scene);
  EXPECT_EQ(piloted.gain, fresh.auto_pilot_gain);
  EXPECT_EQ(piloted.first_spread, fresh.auto_first_spread);

  RenderParams p = st.params;
  EXPECT_EQ(st.apply(RenderParamsEdit{p}), Tier::none) << "unchanged parameters";
  p.max_depth = 7;
  EXPECT_EQ(st.apply(RenderParamsEdit{p}), Tier::camera);
  EXPECT_EQ(st.params.max_depth, 7);

  Material m = st.scene.materials[0];
  m.albedo = vec3(2.0f, 0.5f, -1.0f);
  EXPECT_EQ(st.apply(MaterialEdit{0, m}), Tier::material);
  EXPECT_EQ(st.scene.materials[0].albedo, vec3(1.0f, 0.5f, 0.0f)) << "clamped in one place";
  m.type = MaterialType::glass;
  st.apply(MaterialEdit{0, m});
  EXPECT_EQ(st.scene.materials[0].albedo, vec3(1.0f)) << "glass albedo is 1";
  EXPECT_EQ(st.geo, geo0) << "a material edit keeps the geometry";

  ASSERT_EQ(st.lights.size(), 1u);
  const size_t nodes = st.geo->trace.triangles.node_count;
  EXPECT_EQ(st.apply(LightShapeEdit{0, {}, vec2(0.2f, 0.1f), {}}), Tier::light_refit);
  EXPECT_EQ(st.apply(LightShapeEdit{0, {}, {}, 1.5f}), Tier::light_refit);
  EXPECT_EQ(st.apply(LightShapeEdit{0, vec3(0.1f, 1.95f, 0.0f), {}, {}}), Tier::light_refit);
  EXPECT_EQ(st.geometry_builds, 1) << "light edits never rebuild";
  EXPECT_EQ(st.geometry_refits, 3);
  EXPECT_NE(st.geo, geo0);
  EXPECT_EQ(st.geo->trace.triangles.node_count, nodes) << "a refit keeps the tree";
  LightPlacement pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.size.x, 0.3f, 1e-5f);
  EXPECT_NEAR(pl.size.y, 0.15f, 1e-5f);
  EXPECT_NEAR(pl.center.x, 0.1f, 1e-5f);

  EXPECT_EQ(st.apply(LightEmissionEdit{0, vec3(1.0f, 0.5f, 0.25f), -2.0f}), Tier::material);
  ASSERT_EQ(st.lights.size(), 1u) << "a light switched off stays in the list";
  EXPECT_EQ(st.scene.materials[st.lights[0].material].emission, vec3(0.0f)) << "a negative intensity is off";
  EXPECT_EQ(st.apply(LightEmissionEdit{0, vec3(1.0f, 0.5f, 0.25f), 4.0f}), Tier::material);
  EXPECT_EQ(st.scene.materials[st.lights[0].material].emission, vec3(4.0f, 2.0f, 1.0f));
  EXPECT_EQ(st.geometry_refits, 3) << "colour and intensity need no refit";

  auto loaded = std::make_shared<LoadedScene>();
  loaded->scene = builtin("cornell-spheres");
  loaded->geo = make_render_geometry(loaded->scene);
  EXPECT_EQ(st.apply(SceneEdit{loaded}), Tier::rebuild);
  EXPECT_EQ(st.geometry_builds, 2);
  EXPECT_EQ(st.scene.source, "builtin:cornell-spheres");

  // Rejected edits do nothing.
  const int restarts = st.restarts;
  EXPECT_EQ(st.apply(LightShapeEdit{99, {}, vec2(1.0f), {}}), Tier::none);
  EXPECT_EQ(st.apply(MaterialEdit{-1, {}}), Tier::none);
  Camera degenerate = *st.scene.camera;
  degenerate.eye = degenerate.target;
  EXPECT_EQ(st.apply(CameraEdit{degenerate}), Tier::none);
  EXPECT_EQ(st.restarts, restarts);
}

TEST(Tiers, AnEditToTheValuesAlreadyThereKeepsTheSamples) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, -1);
  ASSERT_EQ(st.lights.size(), 1u);
  const int restarts = st.restarts;
  EXPECT_EQ(st.apply(CameraEdit{*st.scene.camera}), Tier::none) << "the reset camera key at the home camera";
  EXPECT_EQ(st.apply(MaterialEdit{1, st.scene.materials[1]}), Tier::none);
  Material unnormalized = st.scene.materials[1];
  unnormalized.albedo.x = 3.0f;  // clamps to 1: a change unless it was 1 already
  EXPECT_EQ(st.apply(MaterialEdit{1, unnormalized}), Tier::material);
  EXPECT_EQ(st.apply(MaterialEdit{1, unnormalized}), Tier::none) << "the same after normalizing";
  const Material& light = st.scene.materials[st.lights[0].material];
  const float intensity = max_component(light.emission);
  EXPECT_EQ(st.apply(LightEmissionEdit{0, light.emission / intensity, intensity}), Tier::none);
  const LightPlacement pl = light_placement(st.scene, st.lights[0]);
  EXPECT_EQ(st.apply(LightShapeEdit{0, pl.center, {}, {}}), Tier::none);
  EXPECT_EQ(st.apply(LightShapeEdit{0, {}, pl.size, {}}), Tier::none);
  EXPECT_EQ(st.apply(LightShapeEdit{0, {}, {}, 1.0f}), Tier::none);
  EXPECT_EQ(st.restarts, restarts + 1);
  EXPECT_EQ(st.geometry_refits, 0);
  Camera moved = *st.scene.camera;
  moved.fov_deg += 1.0f;
  EXPECT_EQ(st.apply(CameraEdit{moved}), Tier::camera);
  EXPECT_EQ(st.apply(LightShapeEdit{0, pl.center + vec3(0.1f, 0.0f, 0.0f), {}, {}}), Tier::light_refit);
}

TEST(Tiers, TierOfAgreesWithApplyForEveryKind) {
  EXPECT_EQ(tier_of(DisplayEdit{}), Tier::display);
  EXPECT_EQ(tier_of(CameraEdit{}), Tier::camera);
  EXPECT_EQ(tier_of(RenderParamsEdit{}), Tier::camera);
  EXPECT_EQ(tier_of(RestartEdit{}), Tier::camera);
  EXPECT_EQ(tier_of(MaterialEdit{}), Tier::material);
  EXPECT_EQ(tier_of(LightEmissionEdit{}), Tier::material);
  EXPECT_EQ(tier_of(LightShapeEdit{}), Tier::light_refit);
  EXPECT_EQ(tier_of(SceneEdit{}), Tier::rebuild);
  EXPECT_EQ(tier_of(DisplayModeEdit{}), Tier::display);
  EXPECT_EQ(tier_of(AdaptiveEdit{}), Tier::sampling);
  EXPECT_EQ(tier_of(StopEdit{}), Tier::sampling);
  EXPECT_EQ(tier_of(CompareEdit{}), Tier::camera);
  EXPECT_EQ(tier_of(DividerEdit{}), Tier::display);
}

// "Stop at spp" is state, not a session setting: it holds for the sessions there are and for side B started later,
// and it restarts nothing (test_panels checks that the Render panel shows the stop a script set).
TEST(Tiers, TheStopHoldsForBothSidesAndRestartsNothing) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  const int restarts = st.restarts;
  EXPECT_EQ(st.apply(StopEdit{6}), Tier::sampling);
  EXPECT_EQ(st.target_spp, 6);
  EXPECT_EQ(st.session->target_spp(), 6);
  EXPECT_EQ(st.apply(StopEdit{6}), Tier::none) << "unchanged";
  EXPECT_EQ(st.apply(StopEdit{-1}), Tier::none) << "negative";
  EXPECT_EQ(st.target_spp, 6);
  st.apply(CompareEdit{CompareConfig{}});
  ASSERT_TRUE(st.session_b);
  EXPECT_EQ(st.session_b->target_spp(), 6) << "side B started after the stop";
  EXPECT_EQ(st.apply(StopEdit{0}), Tier::sampling);
  EXPECT_EQ(st.session->target_spp(), 0);
  EXPECT_EQ(st.session_b->target_spp(), 0);
  EXPECT_EQ(st.restarts, restarts + 1) << "the compare restarted; the stops did not";
}

// The light panel, the script's `light N` and picking keep an index into the scene's lights: a scene with fewer
// lights, loaded or edited into being, must not leave it pointing past them.
/// The built-in Cornell box with a second ceiling light beside the first (same material).
Scene cornell_with_two_lights() {
  Scene two = builtin("cornell");
  auto lit = std::find_if(two.quads.begin(), two.quads.end(),
                          [&](const Quad& q) { return two.materials[q.material].emissive(); });
  EXPECT_NE(lit, two.quads.end());
  Quad second = *lit;
  second.corner.x -= 0.5f;
  two.quads.push_back(second);
  return two;
}

TEST(Tiers, ASceneWithFewerLightsDropsASelectionPastThem) {
  ViewerState st;
  st.init(cornell_with_two_lights(), small_params(), {}, -1);
  ASSERT_EQ(st.lights.size(), 2u);
  st.selected_light = 1;
  auto loaded = std::make_shared<LoadedScene>();
  loaded->scene = builtin("cornell");
  loaded->geo = make_render_geometry(loaded->scene);
  EXPECT_EQ(st.apply(SceneEdit{loaded}), Tier::rebuild);
  ASSERT_EQ(st.lights.size(), 1u);
  EXPECT_EQ(st.selected_light, -1);
}

// Intensity 0 (the panel's drag goes down to it) switches a light off; it stays in the list, in its place and
// selected, and the same edit switches it on again.
TEST(Tiers, ALightSwitchedOffKeepsItsPlaceAndComesBack) {
  ViewerState st;
  st.init(cornell_with_two_lights(), small_params(), {}, -1);
  const std::vector<SceneLight> before = st.lights;
  ASSERT_EQ(before.size(), 2u);
  st.selected_light = 1;
  EXPECT_EQ(st.apply(LightEmissionEdit{1, vec3(1.0f), 0.0f}), Tier::material);
  EXPECT_FALSE(st.scene.materials[st.lights[1].material].emissive());
  ASSERT_EQ(st.lights.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(st.lights[i].kind, before[i].kind);
    EXPECT_EQ(st.lights[i].shape, before[i].shape);
  }
  EXPECT_EQ(st.selected_light, 1);
  EXPECT_EQ(st.apply(LightEmissionEdit{1, vec3(1.0f, 0.5f, 0.5f), 3.0f}), Tier::material);
  ASSERT_EQ(st.lights.size(), 2u);
  EXPECT_EQ(st.scene.materials[st.lights[1].material].emission, vec3(3.0f, 1.5f, 1.5f));
}

TEST(Tiers, CompareRestartsBothSidesAndEveryEditRestartsBoth) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  CompareConfig b{IntegratorKind::nee, LightSampling::area, SamplerKind::independent, {}};
  const int restarts0 = st.restarts;
  EXPECT_EQ(st.apply(CompareEdit{b}), Tier::camera);
  ASSERT_TRUE(st.session_b);
  EXPECT_EQ(st.restarts, restarts0 + 1);
  EXPECT_EQ(st.session_b->epoch(), 1u);
  // Side A's time slice first: side B waits from the restart on, not from the viewer's next tick.
  EXPECT_FALSE(st.session->paused());
  EXPECT_TRUE(st.session_b->paused());
  EXPECT_EQ(st.params_b().integrator, IntegratorKind::nee);
  EXPECT_EQ(st.params_b().sampler, SamplerKind::independent);
  EXPECT_EQ(st.params_b().width, st.params.width) << "same camera and size";
  EXPECT_EQ(st.apply(CompareEdit{b}), Tier::none) << "unchanged";
  EXPECT_EQ(st.apply(DividerEdit{0.25f}), Tier::display);
  EXPECT_EQ(st.divider, 0.25f);
  for (auto [x, clamped] : {std::pair{1.5f, 1.0f}, std::pair{-0.5f, 0.0f}}) {
    st.apply(DividerEdit{x});
    EXPECT_EQ(st.divider, clamped) << "a divider of " << x;
  }
  EXPECT_EQ(st.apply(DividerEdit{std::numeric_limits<float>::quiet_NaN()}), Tier::none);
  EXPECT_EQ(st.divider, 0.0f);
  st.apply(DividerEdit{0.25f});
  EXPECT_EQ(st.session_b->epoch(), 1u) << "the divider never restarts";
  Camera cam = *st.scene.camera;
  cam.eye.x += 0.2f;
  EXPECT_EQ(st.apply(CameraEdit{cam}), Tier::camera);
  EXPECT_EQ(st.session_b->epoch(), 2u) << "any edit restarts both sides";
  Material m = st.scene.materials[0];
  m.albedo = vec3(0.3f);
  EXPECT_EQ(st.apply(MaterialEdit{0, m}), Tier::material);
  EXPECT_EQ(st.session_b->epoch(), 3u);
  auto j = nlohmann::json::parse(st.stats_json());
  ASSERT_TRUE(j.contains("compare"));
  for (const char* side : {"a", "b"})
    for (const char* key : {"spp", "seconds", "est_rel_mse", "rel_mse"}) EXPECT_TRUE(j["compare"][side].contains(key)) << key;
  EXPECT_EQ(j["compare"]["b"]["integrator"], "nee");
  const uint64_t a_epoch = st.session->epoch();
  EXPECT_EQ(st.apply(CompareEdit{}), Tier::display) << "compare off keeps A's accumulation";
  EXPECT_EQ(st.session->epoch(), a_epoch);
  EXPECT_TRUE(st.session_b->paused());
  EXPECT_FALSE(nlohmann::json::parse(st.stats_json()).contains("compare"));
  EXPECT_EQ(st.apply(CompareEdit{}), Tier::none);
}

TEST(Tiers, DisplayModesAndAdaptiveSamplingNeverRestart) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  const uint64_t epoch0 = st.session->epoch();
  const int restarts0 = st.restarts;
  for (DisplayMode m : {DisplayMode::error, DisplayMode::samples, DisplayMode::image}) {
    st.display_dirty = false;
    EXPECT_EQ(st.apply(DisplayModeEdit{m}), Tier::display);
    EXPECT_EQ(st.display_mode, m);
    EXPECT_TRUE(st.display_dirty) << "the shown image must be rebuilt";
  }
  EXPECT_EQ(st.apply(DisplayModeEdit{DisplayMode::reference_error}), Tier::none) << "no reference";
  EXPECT_EQ(st.display_mode, DisplayMode::image);
  st.reference = Image(32, 24);
  EXPECT_EQ(st.apply(DisplayModeEdit{DisplayMode::reference_error}), Tier::display);

  AdaptiveParams a;
  a.noise_threshold = 0.1;
  EXPECT_EQ(st.apply(AdaptiveEdit{a}), Tier::sampling);
  EXPECT_EQ(st.apply(AdaptiveEdit{a}), Tier::none) << "unchanged";
  a.noise_threshold = 0.01;  // lowering resumes stopped pixels in the same epoch
  EXPECT_EQ(st.apply(AdaptiveEdit{a}), Tier::sampling);
  EXPECT_EQ(st.adaptive.noise_threshold, 0.01);
  for (double bad : {-0.5, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    AdaptiveParams b = a;
    b.noise_threshold = bad;
    EXPECT_EQ(st.apply(AdaptiveEdit{b}), Tier::none) << bad;
  }
  EXPECT_EQ(st.adaptive.noise_threshold, 0.01);
  EXPECT_EQ(st.apply(AdaptiveEdit{AdaptiveParams{}}), Tier::sampling) << "off";
  EXPECT_EQ(st.restarts, restarts0);
  EXPECT_EQ(st.session->epoch(), epoch0);
}

TEST(DisplayModes, HeatmapsShowTheMapsAndFallBackToTheImage) {
  SessionFrame f;
  f.image = Image(4, 2);
  for (float& v : f.image.rgb) v = 0.5f;
  Image out;
  HeatLegend legend;
  EXPECT_FALSE(make_display_image(DisplayMode::error, f, nullptr, out, legend)) << "no map published yet";
  EXPECT_EQ(out.rgb, f.image.rgb);
  f.rel_error = Image(4, 2);
  for (size_t i = 0; i < 8; ++i) f.rel_error.set(int(i % 4), int(i / 4), vec3(float(std::pow(10.0, -3.0 + double(i) / 2))));
  f.rel_error.set(0, 0, vec3(std::numeric_limits<float>::infinity()));
  ASSERT_TRUE(make_display_image(DisplayMode::error, f, nullptr, out, legend));
  EXPECT_TRUE(legend.log);
  EXPECT_EQ(out.at(0, 0), vec3(0.18f)) << "unknown error is grey";
  for (int i = 2; i < 7; ++i)  // brighter with larger error up to the top of the scale (1) (the colour map's luminance increases)
    EXPECT_GT(glm::dot(out.at(i % 4, i / 4), vec3(0.2126f, 0.7152f, 0.0722f)),
              glm::dot(out.at((i - 1) % 4, (i - 1) / 4), vec3(0.2126f, 0.7152f, 0.0722f))) << i;
  f.spp_map = Image(4, 2);
  f.spp_map.set(3, 1, vec3(64.0f));
  ASSERT_TRUE(make_display_image(DisplayMode::samples, f, nullptr, out, legend));
  EXPECT_EQ(legend.hi, 64.0);
  EXPECT_NE(out.at(3, 1), out.at(0, 0));
  EXPECT_EQ(out.at(1, 0), out.at(0, 0));
  Image ref = f.image;
  ref.set(1, 1, vec3(0.25f));  // |0.5 - 0.25| / 0.25 = 1: the top of the scale; elsewhere 0: the bottom
  ASSERT_TRUE(make_display_image(DisplayMode::reference_error, f, &ref, out, legend));
  EXPECT_GT(out.at(1, 1).x, 0.9f);  // the top colour (0.99, 1, 0.64) in sRGB
  EXPECT_LT(out.at(0, 0).x, 1e-3f);
  // An error of 10^-1.5 sits in the middle of the log scale (1e-3 to 1): the colour map's middle stop, (0.73, 0.21,
  // 0.33) in sRGB, linear in the image (the display's framebuffer encodes sRGB), in both heatmaps.
  auto decode = [](float s) { return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f); };
  const vec3 middle(decode(0.73f), decode(0.21f), decode(0.33f));
  const float mid = float(std::pow(10.0, -1.5));
  ref.set(2, 1, vec3(0.5f / (1.0f + mid)));  // |0.5 - ref| / ref = mid
  ASSERT_TRUE(make_display_image(DisplayMode::reference_error, f, &ref, out, legend));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.at(2, 1)[c], middle[c], 2e-3f) << "reference error, channel " << c;
  f.rel_error.set(2, 1, vec3(mid));
  ASSERT_TRUE(make_display_image(DisplayMode::error, f, nullptr, out, legend));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.at(2, 1)[c], middle[c], 2e-3f) << "relative error, channel " << c;
  // The error of the pixel's total over the channels, not of one channel: here green alone differs, 0.25 of 1.25.
  ref.set(0, 1, vec3(0.5f, 0.25f, 0.5f));
  ASSERT_TRUE(make_display_image(DisplayMode::reference_error, f, &ref, out, legend));
  const vec3 fifth = heat_srgb(float((std::log10(0.2) + 3.0) / 3.0));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.at(0, 1)[c], decode(fifth[c]), 2e-3f) << "green error, channel " << c;
  Image other(2, 2);
  EXPECT_FALSE(make_display_image(DisplayMode::reference_error, f, &other, out, legend)) << "size differs";
}

/// Waits for a frame of the session's current epoch (generous deadline: a hang, not slowness, fails).
bool fetch_current(ViewerState& st) {
  for (int i = 0; i < 6000; ++i) {
    if (st.session->fetch(st.frame) && st.frame.epoch == st.session->epoch()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

TEST(Tiers, EveryRestartShowsAReducedResolutionPreviewFirst) {
  ViewerState st;
  RenderParams p = small_params();
  p.width = 64;
  p.height = 48;
  st.preview_div = 4;
  st.init(builtin("cornell"), p, {}, 1);
  st.session->set_paused(true);  // paused: the driver renders a restart's preview, then waits
  Camera cam = *st.scene.camera;
  for (int k = 0; k < 3; ++k) {
    cam.eye.x += 0.1f;
    ASSERT_EQ(st.apply(CameraEdit{cam}), Tier::camera);
    ASSERT_TRUE(fetch_current(st));
    EXPECT_TRUE(st.frame.preview) << "restart " << k;
    EXPECT_EQ(st.frame.width, 16);
    EXPECT_EQ(st.frame.height, 12);
    EXPECT_EQ(st.frame.frames, 0);
  }
}

TEST(Tiers, LoweringTheThresholdResumesStoppedPixelsInTheSameEpoch) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  const uint64_t epoch0 = st.session->epoch();
  AdaptiveParams a;
  a.noise_threshold = 1.0;  // loose: every pixel stops soon after its minimum
  a.min_spp = 2;
  ASSERT_EQ(st.apply(AdaptiveEdit{a}), Tier::sampling);
  // Wait (deadline 60 s: a hang, not slowness, fails) until adaptive sampling has stopped every pixel.
  bool converged = false;
  for (int i = 0; i < 6000 && !converged; ++i) {
    if (st.session->fetch(st.frame)) converged = st.frame.converged;
    if (!converged) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(converged);
  const int spp_stopped = st.frame.spp;
  a.noise_threshold = 0.001;  // strict: the stopped pixels resume
  ASSERT_EQ(st.apply(AdaptiveEdit{a}), Tier::sampling);
  bool resumed = false;
  for (int i = 0; i < 6000 && !resumed; ++i) {
    if (st.session->fetch(st.frame)) resumed = st.frame.spp > spp_stopped && !st.frame.converged;
    if (!resumed) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(resumed) << "spp stayed at " << spp_stopped;
  EXPECT_EQ(st.frame.epoch, epoch0) << "no restart";
  EXPECT_EQ(st.session->epoch(), epoch0);
}

TEST(Tiers, TheOldSceneStaysLiveWhileALoadRuns) {
  TempDir dir;
  std::string obj = write_two_triangle_light_obj(dir.path);
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  ASSERT_TRUE(fetch_current(st));
  const uint64_t epoch = st.session->epoch();
  auto rs = st.render_scene;
  st.start_load(obj);
  ASSERT_TRUE(st.loading.valid());
  // The load runs in the background; until poll_load installs it, the old scene renders on, frame after frame.
  st.loading.wait();
  EXPECT_EQ(st.render_scene, rs);
  EXPECT_EQ(st.session->epoch(), epoch);
  int frames = st.frame.frames;
  for (int i = 0; i < 6000 && st.frame.frames <= frames + 1; ++i) {
    st.session->fetch(st.frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_GT(st.frame.frames, frames + 1);
  EXPECT_EQ(st.frame.epoch, epoch);
  EXPECT_TRUE(st.poll_load());
  EXPECT_NE(st.session->epoch(), epoch);
  EXPECT_EQ(st.scene.source, obj);
  EXPECT_EQ(st.geometry_builds, 2);
}

// The restart-latency summary (stats JSON and Stats panel): the nearest rank of the sorted values, whatever the
// order they were recorded in.
TEST(Stats, LatencyPercentilesAreNearestRanksOfTheSortedValues) {
  EXPECT_EQ(percentile({}, 0.5), 0.0);
  EXPECT_EQ(percentile({7.0}, 0.95), 7.0);
  EXPECT_EQ(percentile({30, 10, 100, 20}, 0.5), 30.0);   // sorted 10 20 30 100: rank round(1.5) = 2
  EXPECT_EQ(percentile({30, 10, 100, 20}, 0.95), 100.0);
  std::vector<double> v;
  for (int i = 0; i < 100; ++i) v.push_back(double((i * 37) % 100));  // 0..99 shuffled
  EXPECT_EQ(percentile(v, 0.5), 50.0);
  EXPECT_EQ(percentile(v, 0.95), 94.0);
  EXPECT_EQ(percentile(v, 0.0), 0.0);
  EXPECT_EQ(percentile(v, 1.0), 99.0);
}

/// Loads the scene file `path` into `st`.
void open_file(ViewerState& st, const std::string& path) {
  Result<Scene> s = load_scene(path);
  ASSERT_TRUE(s.ok()) << s.error();
  st.init(std::move(*s), small_params(), {}, -1);
}

TEST(SceneLights, APlacementIsTheSameAtAnyScale) {
  // Two emissive triangles forming a 0.4 x 0.2 rectangle at (0.5, 1, 0.5), scaled by s: the placement scales with
  // it (areas and normals in double: their float squares vanish below about 1e-10 across).
  for (float s : {1.0f, 1e-15f, 1e15f}) {
    Scene scene;
    Material light;
    light.emission = vec3(5.0f);
    scene.materials.push_back(light);
    Mesh m;
    m.positions = {vec3(0.3f, 1, 0.4f), vec3(0.7f, 1, 0.4f), vec3(0.7f, 1, 0.6f), vec3(0.3f, 1, 0.6f)};
    for (vec3& p : m.positions) p *= s;
    m.indices = {uvec3(0, 2, 1), uvec3(0, 3, 2)};
    m.materials = {0, 0};
    scene.meshes.push_back(m);
    const std::vector<SceneLight> lights = find_scene_lights(scene);
    ASSERT_EQ(lights.size(), 1u) << s;
    const LightPlacement pl = light_placement(scene, lights[0]);
    EXPECT_NEAR(pl.center.x / s, 0.5f, 1e-6f) << s;
    EXPECT_NEAR(pl.center.y / s, 1.0f, 1e-6f) << s;
    EXPECT_NEAR(pl.center.z / s, 0.5f, 1e-6f) << s;
    EXPECT_NEAR(std::max(pl.size.x, pl.size.y) / s, 0.4f, 1e-6f) << s;
    EXPECT_NEAR(std::min(pl.size.x, pl.size.y) / s, 0.2f, 1e-6f) << s;
  }
}

TEST(SceneLights, TwoEmissiveTrianglesAreOneLightResizedInTheirPlane) {
  TempDir dir;
  ViewerState st;
  open_file(st, write_two_triangle_light_obj(dir.path));
  ASSERT_EQ(st.lights.size(), 1u);
  EXPECT_EQ(st.lights[0].kind, SceneLightKind::triangles);
  EXPECT_EQ(st.lights[0].triangles.size(), 2u);
  LightPlacement pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.center.x, 0.5f, 1e-6f);
  EXPECT_NEAR(pl.center.y, 1.0f, 1e-6f);
  EXPECT_NEAR(pl.center.z, 0.5f, 1e-6f);
  EXPECT_NEAR(pl.size.x, 0.4f, 1e-6f);  // the first boundary edge runs along x
  EXPECT_NEAR(pl.size.y, 0.2f, 1e-6f);
  // Corners of the non-emissive triangles (the floor, and the ceiling strip sharing two of the light's corners).
  auto other_corners = [&] {
    std::vector<vec3> out;
    const Mesh& m = st.scene.meshes[0];
    for (size_t t = 0; t < m.indices.size(); ++t)
      if (!st.scene.materials[m.materials[t]].emissive())
        for (int k = 0; k < 3; ++k) out.push_back(m.positions[m.indices[t][k]]);
    return out;
  };
  const std::vector<vec3> others_before = other_corners();
  ASSERT_EQ(others_before.size(), 12u);

  ASSERT_EQ(st.apply(LightShapeEdit{0, {}, vec2(0.6f, 0.1f), {}}), Tier::light_refit);
  pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.size.x, 0.6f, 1e-6f);
  EXPECT_NEAR(pl.size.y, 0.1f, 1e-6f);
  EXPECT_NEAR(pl.center.x, 0.5f, 1e-6f);
  EXPECT_NEAR(pl.center.z, 0.5f, 1e-6f);
  // The ceiling strip that shared two of the light's corners did not move.
  EXPECT_EQ(other_corners(), others_before);
  // The render geometry followed: a ray up through the new light's edge region hits the light's material.
  const RenderGeometry& g = *st.geo;
  int light_tris = 0;
  for (uint32_t t = 0; t < g.triangle_count(); ++t)
    if (st.scene.materials[g.tri_material[t]].emissive()) {
      ++light_tris;
      for (int k = 0; k < 3; ++k) {
        vec3 p = g.tri_vertices[3 * t + k] + g.origin;
        EXPECT_NEAR(std::abs(p.x - 0.5f), 0.3f, 1e-6f);
        EXPECT_NEAR(std::abs(p.z - 0.5f), 0.05f, 1e-6f);
      }
    }
  EXPECT_EQ(light_tris, 2);
  EXPECT_EQ(st.geometry_builds, 1);
  // The scale works on it too, and on the render side the light set follows.
  ASSERT_EQ(st.apply(LightShapeEdit{0, {}, {}, 0.5f}), Tier::light_refit);
  pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.size.x, 0.3f, 1e-6f);
  float area = 0.0f;
  for (const Light& l : st.render_scene->lights.lights) area += l.area;
  EXPECT_NEAR(area, 0.3f * 0.05f, 1e-6f);
}

TEST(SceneLights, TouchingLightsOfTwoMaterialsAreTwoLights) {
  // Two emissive panels side by side, sharing an edge (two vertices), one red and one blue: one light each, so the
  // Lights panel edits each colour on its own.
  TempDir dir;
  std::ofstream(dir.path / "panels.mtl")
      << "newmtl red\nKe 4 0 0\nnewmtl blue\nKe 0 0 4\nnewmtl white\nKd 0.5 0.5 0.5\n";
  std::ofstream(dir.path / "panels.obj") << "mtllib panels.mtl\n"
                                            "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\nv 2 1 0\nv 2 1 1\n"
                                            "v -1 0 -1\nv 3 0 -1\nv 3 0 2\nv -1 0 2\n"
                                            "usemtl red\nf 1 2 3\nf 1 3 4\n"
                                            "usemtl blue\nf 2 5 6\nf 2 6 3\n"
                                            "usemtl white\nf 7 10 9 8\n";
  ViewerState st;
  open_file(st, (dir.path / "panels.obj").string());
  ASSERT_EQ(st.lights.size(), 2u);
  for (int l = 0; l < 2; ++l) {
    const SceneLight& light = st.lights[size_t(l)];
    EXPECT_EQ(light.triangles.size(), 2u) << l;
    const std::string name = st.scene.materials[light.material].name;
    EXPECT_EQ(name, l == 0 ? "red" : "blue");
    for (uint32_t t : light.triangles) EXPECT_EQ(st.scene.meshes[0].materials[t], light.material) << name;
    EXPECT_NEAR(light_placement(st.scene, light).center.x, l == 0 ? 0.5f : 1.5f, 1e-6f) << name;
  }
}

/// Opens in `st` an OBJ of `body` (vertices and faces), every face of the emissive material "lamp".
void open_lamp_obj(ViewerState& st, const TempDir& dir, const std::string& body) {
  std::ofstream(dir.path / "lamp.mtl") << "newmtl lamp\nKe 5 5 5\n";
  std::ofstream(dir.path / "lamp.obj") << "mtllib lamp.mtl\nusemtl lamp\n" << body;
  open_file(st, (dir.path / "lamp.obj").string());
}

TEST(SceneLights, AShearedTriangleLightIsMeasuredAndResizedAlongItsSides) {
  // A parallelogram light of two triangles, sides (1, 0, 0) and (0.5, 0, 1): its size is the sides' lengths, not
  // its extent along x and z, and a resize stretches it along a side, keeping the other.
  TempDir dir;
  ViewerState st;
  open_lamp_obj(st, dir, "v 0 1 0\nv 1 1 0\nv 1.5 1 1\nv 0.5 1 1\nf 1 2 3\nf 1 3 4\n");
  ASSERT_EQ(st.lights.size(), 1u);
  const float side = std::sqrt(1.25f);
  LightPlacement pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.size.x, 1.0f, 1e-6f);
  EXPECT_NEAR(pl.size.y, side, 1e-6f);
  EXPECT_NEAR(glm::length(pl.center - vec3(0.75f, 1.0f, 0.5f)), 0.0f, 1e-6f);
  ASSERT_EQ(st.apply(LightShapeEdit{0, {}, vec2(2.0f, side), {}}), Tier::light_refit);
  pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.size.x, 2.0f, 1e-5f);
  EXPECT_NEAR(pl.size.y, side, 1e-5f);
  float area = 0.0f;
  for (const Light& l : st.render_scene->lights.lights) area += l.area;
  EXPECT_NEAR(area, 2.0f, 1e-5f) << "twice the area: stretched along one side";
  std::vector<vec3> corners;
  const Mesh& m = st.scene.meshes[0];
  for (uvec3 t : m.indices)
    for (int k = 0; k < 3; ++k) corners.push_back(m.positions[t[k]]);
  for (vec3 want : {vec3(-0.5f, 1, 0), vec3(1.5f, 1, 0), vec3(2, 1, 1), vec3(0, 1, 1)})
    EXPECT_TRUE(std::any_of(corners.begin(), corners.end(), [&](vec3 c) { return glm::length(c - want) < 1e-5f; }))
        << want.x << " " << want.y << " " << want.z;
}

TEST(SceneLights, ResizingAFoldedLightKeepsItsRelief) {
  // Two emissive triangles meeting at a fold (one corner raised): a resize works in the light's mean plane and
  // keeps each corner's height above it, so resizing to the size it has changes nothing. That is resize_light's
  // arithmetic, tested here directly: through apply, the same size is no edit at all
  // (AnEditToTheValuesAlreadyThereKeepsTheSamples), and twice the size and back must refit each way.
  TempDir dir;
  ViewerState st;
  open_lamp_obj(st, dir, "v 0 1 0\nv 1 1.2 0\nv 1 1 1\nv 0 1 1\nf 1 3 2\nf 1 4 3\n");
  ASSERT_EQ(st.lights.size(), 1u);
  const std::vector<vec3> before = st.scene.meshes[0].positions;
  const LightPlacement pl = light_placement(st.scene, st.lights[0]);
  ASSERT_TRUE(resize_light(st.scene, st.lights[0], pl.size));
  const std::vector<vec3>& after = st.scene.meshes[0].positions;
  ASSERT_EQ(after.size(), before.size());
  for (size_t i = 0; i < before.size(); ++i)
    EXPECT_NEAR(glm::length(after[i] - before[i]), 0.0f, 1e-5f) << "corner " << i;
  ASSERT_EQ(st.apply(LightShapeEdit{0, {}, 2.0f * pl.size, {}}), Tier::light_refit);
  ASSERT_EQ(st.apply(LightShapeEdit{0, {}, pl.size, {}}), Tier::light_refit);
}

TEST(SceneLights, AMovedLightIsWhereTheSavedSceneLoadsIt) {
  // Moving a light of an OBJ changes the mesh: the saved scene must write the mesh out rather than name its file,
  // whose light is where it was.
  TempDir dir;
  ViewerState st;
  open_file(st, write_two_triangle_light_obj(dir.path));
  ASSERT_EQ(st.lights.size(), 1u);
  ASSERT_EQ(st.apply(LightShapeEdit{0, vec3(0.5f, 0.9f, 0.25f), {}, {}}), Tier::light_refit);
  const std::string out = (dir.path / "moved.json").string();
  ASSERT_FALSE(st.save_scene(out).has_value());
  Result<Scene> back = load_scene(out);
  ASSERT_TRUE(back.ok()) << back.error();
  const std::vector<SceneLight> lights = find_scene_lights(*back);
  ASSERT_EQ(lights.size(), 1u);
  const LightPlacement pl = light_placement(*back, lights[0]);
  EXPECT_NEAR(glm::length(pl.center - vec3(0.5f, 0.9f, 0.25f)), 0.0f, 1e-5f);
}

TEST(SceneLights, AFarMeshLightIsPlacedInWorldSpace) {
  // Far from the origin a mesh keeps its positions relative to an origin in double (scene.h): the light's
  // placement, and a move to a world position, are in world space all the same.
  TempDir dir;
  write_two_triangle_light_obj(dir.path);
  const std::string json = (dir.path / "far.json").string();
  std::ofstream(json) << R"({"shapes": [{"type": "mesh", "file": "room.obj",)"
                          R"( "transform": {"translate": [100000, 0, 0]}}]})";
  ViewerState st;
  open_file(st, json);
  ASSERT_EQ(st.lights.size(), 1u);
  LightPlacement pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.center.x, 100000.5f, 0.02f);
  EXPECT_NEAR(pl.center.y, 1.0f, 1e-5f);
  ASSERT_EQ(st.apply(LightShapeEdit{0, vec3(100000.25f, 0.5f, 0.5f), {}, {}}), Tier::light_refit);
  pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(pl.center.x, 100000.25f, 0.02f);
  EXPECT_NEAR(pl.center.y, 0.5f, 1e-5f);
}

TEST(SceneLights, EveryLightOfEveryBuiltinSceneCanBeResizedAndScaled) {
  for (const BuiltinAsset& a : builtin_assets()) {
    if (std::string_view(a.name) == "cornell-large-mesh") continue;  // a 1M-triangle BVH: slow under sanitizers
    ViewerState st;
    st.init(builtin(a.name), small_params(), {}, -1);
    ASSERT_FALSE(st.lights.empty()) << a.name;
    for (int l = 0; l < int(st.lights.size()); ++l) {
      LightPlacement before = light_placement(st.scene, st.lights[size_t(l)]);
      if (st.lights[size_t(l)].kind != SceneLightKind::sphere) {
        ASSERT_EQ(st.apply(LightShapeEdit{l, {}, before.size * vec2(1.5f, 0.5f), {}}), Tier::light_refit) << a.name;
        LightPlacement after = light_placement(st.scene, st.lights[size_t(l)]);
        EXPECT_NEAR(after.size.x, 1.5f * before.size.x, 1e-5f) << a.name << " light " << l;
        EXPECT_NEAR(after.size.y, 0.5f * before.size.y, 1e-5f) << a.name << " light " << l;
        EXPECT_NEAR(glm::length(after.center - before.center), 0.0f, 1e-5f) << a.name << " light " << l;
      }
      LightPlacement mid = light_placement(st.scene, st.lights[size_t(l)]);
      ASSERT_EQ(st.apply(LightShapeEdit{l, {}, {}, 2.0f}), Tier::light_refit) << a.name;
      LightPlacement after = light_placement(st.scene, st.lights[size_t(l)]);
      EXPECT_NEAR(after.size.x, 2.0f * mid.size.x, 1e-5f) << a.name << " light " << l;
      EXPECT_NEAR(glm::length(after.center - mid.center), 0.0f, 1e-5f) << a.name << " light " << l;
    }
    EXPECT_EQ(st.geometry_builds, 1) << a.name;
  }
}

TEST(SceneLights, ASphereLightMovesAndScalesAboutItsCenter) {
  // No built-in scene has a sphere light: the test above never scales one.
  Scene s = floor_under_a_sphere_light();
  ViewerState st;
  st.init(std::move(s), small_params(), {}, -1);
  ASSERT_EQ(st.lights.size(), 1u);
  ASSERT_EQ(st.lights[0].kind, SceneLightKind::sphere);
  ASSERT_EQ(st.apply(LightShapeEdit{0, {}, {}, 2.0f}), Tier::light_refit);
  EXPECT_FLOAT_EQ(st.scene.spheres[0].radius, 0.4f);
  EXPECT_EQ(st.scene.spheres[0].center, vec3(0.5f, 1.5f, -0.25f));
  ASSERT_EQ(st.render_scene->lights.lights.size(), 1u);
  EXPECT_FLOAT_EQ(st.render_scene->lights.lights[0].radius, 0.4f);  // the render side follows
  ASSERT_EQ(st.apply(LightShapeEdit{0, vec3(-0.5f, 1.0f, 0.0f), {}, {}}), Tier::light_refit);
  EXPECT_EQ(st.scene.spheres[0].center, vec3(-0.5f, 1.0f, 0.0f));
  EXPECT_FLOAT_EQ(st.scene.spheres[0].radius, 0.4f);
  const LightPlacement pl = light_placement(st.scene, st.lights[0]);
  EXPECT_NEAR(glm::length(pl.center - vec3(-0.5f, 1.0f, 0.0f)), 0.0f, 1e-6f);
  EXPECT_NEAR(pl.size.x, 0.8f, 1e-6f);
}

TEST(SceneLights, LabelsNameTheShape) {
  // A quad light with a right angle is a rectangle, a sheared one a parallelogram (sampled differently:
  // render/light.h); sizes are the extents along the light's two edges.
  Scene s;
  Material lamp;
  lamp.name = "lamp";
  lamp.emission = vec3(1.0f);
  s.materials.push_back(lamp);
  s.quads.push_back({vec3(0), vec3(2, 0, 0), vec3(0, 0, -1), 0});
  s.quads.push_back({vec3(0), vec3(2, 0, 0), vec3(1, 0, -1), 0});
  ViewerState st;
  st.init(std::move(s), small_params(), {}, -1);
  ASSERT_EQ(st.lights.size(), 2u);
  EXPECT_EQ(light_label(st.scene, st.lights[0]), "lamp (rectangle 2 x 1)");
  EXPECT_EQ(light_label(st.scene, st.lights[1]).rfind("lamp (parallelogram", 0), 0u)
      << light_label(st.scene, st.lights[1]);
}

TEST(SceneLights, PickingALightSelectsIt) {
  ViewerState st;
  RenderParams p = small_params();
  p.width = p.height = 64;
  Scene s = builtin("cornell");
  s.camera->target = vec3(0.0f, 1.98f, 0.0f);  // look straight at the light from below
  s.camera->eye = vec3(0.0f, 1.0f, 0.0f);
  s.camera->up = vec3(0, 0, -1);
  st.init(std::move(s), p, {}, -1);
  ASSERT_TRUE(st.select_at(32, 32));
  EXPECT_EQ(st.selected_light, 0);
  EXPECT_EQ(st.scene.materials[size_t(st.selected_material)].name, "light");
}

// parse_script on every malformed form: each line alone must fail at line 2, naming the reason.
TEST(Script, EveryMalformedFormIsRejectedWithItsLine) {
  struct Case {
    const char* line;
    const char* reason;
  };
  const Case cases[] = {
      {"frobnicate 1", "unknown command"},
      {"orbit 10", "takes 2 argument"},
      {"orbit 1 2 3", "takes 2 argument"},
      {"quit now", "takes 0 argument"},
      {"orbit ten 2", "is not a number"},
      {"dolly nan", "is not a number"},
      {"dolly 0", "is not positive"},
      {"wait-frames -1", "not a non-negative integer"},
      {"wait-ms 1.5", "not a non-negative integer"},
      {"light 0.5", "not a non-negative integer"},
      {"light-size 1", "takes 2 argument"},
      {"light-size 1 -2", "is not positive"},
      {"light-scale 0", "is not positive"},
      {"light-intensity x", "is not a number"},
      {"set-material", "takes 1 to 4 argument"},
      {"set-material plastic", "unknown material type"},
      {"set-material diffuse albedo=1,2", "wrong number of values"},
      {"set-material diffuse albedo=1,x,2", "not a list of numbers"},
      {"set-material diffuse roughness=1", "expected albedo"},
      {"tonemap Reinhard", "unknown tonemap"},
      {"exposure", "takes 1 argument"},
      {"display heat", "unknown display mode"},
      {"compare", "takes 1 to 4 argument"},
      {"compare integrator=path", "expected off, integrator="},
      {"compare sampler", "expected off, integrator="},
      {"compare adaptive=0", "expected off, integrator="},
      {"compare adaptive=2", "expected off, integrator="},
      {"compare off integrator=nee", "expected off, integrator="},
      {"divider 1.5", "not a fraction from 0 to 1"},
      {"divider x", "is not a number"},
      {"display", "takes 1 argument"},
      {"noise-threshold 2", "from 0 (off) to 1"},
      {"noise-threshold -0.1", "from 0 (off) to 1"},
      {"noise-threshold x", "is not a number"},
      {"noise-threshold 0.1 2.5", "the minimum spp must be an integer"},
      {"noise-threshold 0.1 16777217", "the minimum spp must be an integer"},
      {"wait-frames 1e10", "not a non-negative integer"},
      {"set-material diffuse albedo=1,2,3,", "not a list of numbers"},
      {"window 640", "takes 2 argument"},
      {"window 0 480", "not a window size from 1 to 16384"},
      {"window 640 480.5", "not a window size from 1 to 16384"},
      {"window 16385 480", "not a window size from 1 to 16384"},
      {"window 640 x", "is not a number"},
      {"pause", "takes 1 argument"},
      {"pause yes", "is neither on nor off"},
  };
  for (const Case& c : cases) {
    auto r = parse_script(std::string("wait-frames 1  # fine\n") + c.line + "\n", "s.txt");
    ASSERT_FALSE(r.ok()) << c.line;
    EXPECT_EQ(r.error().rfind("s.txt:2: ", 0), 0u) << r.error();
    EXPECT_NE(r.error().find(c.reason), std::string::npos) << c.line << " -> " << r.error();
  }
}

/// A run of `text` (parsed as the file "s.txt"), not started.
ScriptRun parsed_run(const std::string& text) {
  Result<std::vector<ScriptCommand>> commands = parse_script(text, "s.txt");
  EXPECT_TRUE(commands.ok()) << commands.error();
  ScriptRun run;
  run.file = "s.txt";
  if (commands.ok()) run.commands = *commands;
  return run;
}

/// Runs `text` as a --script on `st` the way the viewer's loop does (a finished load, the script's step, the
/// compare's time slices, the newest frames), without a window. Returns the run once it is done, or after 60 s.
ScriptRun run_script(ViewerState& st, const std::string& text) {
  ScriptRun run = parsed_run(text);
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!run.done() && !run.quit && std::chrono::steady_clock::now() < end) {
    st.poll_load();
    run.step(st);
    st.tick_compare();
    st.fetch_frame();
    st.fetch_frame_b();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_TRUE(run.done()) << "timed out at command " << run.next;
  return run;
}

// A script file goes through the one file reader: its text is parsed under its path, and a missing file, a folder or
// a FIFO is refused with the reason, the FIFO unread (a 20 s watchdog writes to it if the load waits on it).
TEST(Script, AScriptFileIsReadOrRefusedWithItsReason) {
  TempDir dir;
  const std::string file = dir.write("s.txt", "wait-frames 1\nbogus\n");
  Result<std::vector<ScriptCommand>> r = load_script(file);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.error().starts_with(file + ":2: ")) << r.error();
  ASSERT_TRUE(load_script(dir.write("ok.txt", "wait-frames 1\n")).ok());
  EXPECT_EQ(load_script(dir / "none.txt").error(), (dir / "none.txt") + ": cannot open: No such file or directory");
  EXPECT_EQ(load_script(dir.path.string()).error(), dir.path.string() + ": cannot open: is a directory");
  const std::string fifo = dir / "pipe.txt";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const Result<std::vector<ScriptCommand>> f = test::load_with_fifo_watchdog(fifo, [&] { return load_script(fifo); });
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error(), fifo + ": cannot open: not a regular file");
}

TEST(Script, CommandsDoWhatTheReadmeSays) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  // A wait restarts nothing: the check after it passes however the command before it restarted.
  EXPECT_EQ(run_script(st, "orbit 10 0\nwait-frames 1\nexpect-no-restart\n").failures, 0);
  // set-material sets the picked material's type.
  EXPECT_EQ(run_script(st, "pick 16 12\nset-material specular albedo=0.5,0.5,0.5\nwait-frames 1\n").failures, 0);
  ASSERT_GE(st.selected_material, 0);
  EXPECT_EQ(st.scene.materials[size_t(st.selected_material)].type, MaterialType::specular);
  // What cannot be done is a counted failure: here a pick outside the image.
  EXPECT_EQ(run_script(st, "pick 32 0\n").failures, 1);
}

// Counts are read whole: as floats, 16777217 samples (2^24 + 1) were 16777216.
TEST(Script, CountsPast2To24AreReadExactly) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  EXPECT_EQ(run_script(st, "stop-at-spp 16777217\n").failures, 0);
  EXPECT_EQ(st.target_spp, 16777217);
  EXPECT_EQ(run_script(st, "stop-at-spp 999999999\n").failures, 0);
  EXPECT_EQ(st.target_spp, 999999999);
}

TEST(Script, ImpossibleCommandsAreCountedFailures) {
  {
    ViewerState st;  // nothing picked yet: set-material changes nothing
    st.init(builtin("cornell"), small_params(), {}, 1);
    const std::vector<Material> before = st.scene.materials;
    EXPECT_EQ(run_script(st, "set-material specular\n").failures, 1);
    EXPECT_EQ(st.scene.materials.size(), before.size());
    for (size_t m = 0; m < before.size(); ++m) EXPECT_EQ(st.scene.materials[m].type, before[m].type) << m;
    // A pixel far off the image is off it (the float of 1e12 did not fit an int).
    EXPECT_EQ(run_script(st, "pick 1e12 5\npick -3e9 5\n").failures, 2);
    EXPECT_EQ(st.selected_material, -1);
  }
  Scene s = floor_under_a_sphere_light();
  ViewerState st;
  st.init(std::move(s), small_params(), {}, 1);
  EXPECT_EQ(run_script(st, "light-size 1 1\n").failures, 1);  // a sphere has no W x H
}

/// Steps `run` once with the window as the viewer reports it; returns the size the script asked the window for.
std::optional<std::array<int, 2>> step_with_window(ScriptRun& run, ViewerState& st, WindowView view) {
  run.window = view;
  run.step(st);
  return run.window_request;
}

// `window W H` without a window: it asks once, then waits until the window has the size and the render has followed
// the area (or the size is locked), then the next command runs.
TEST(Script, WindowAsksForTheSizeAndWaitsForTheRenderToFollow) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);  // 32 x 24
  ScriptRun run = parsed_run("window 600 500\nquit\n");
  EXPECT_EQ(step_with_window(run, st, {1000, 760, 640, 760, false}), (std::array<int, 2>{600, 500}));
  EXPECT_EQ(run.next, 0u);
  EXPECT_FALSE(step_with_window(run, st, {1000, 760, 640, 760, false}));  // asked once only
  EXPECT_FALSE(step_with_window(run, st, {600, 500, 240, 500, false}));   // resized; the render not yet
  EXPECT_EQ(run.next, 0u);
  RenderParams p = st.params;
  p.width = 240;
  p.height = 500;
  st.apply(RenderParamsEdit{p});
  step_with_window(run, st, {600, 500, 240, 500, false});
  EXPECT_TRUE(run.quit);
  EXPECT_EQ(run.failures, 0);
  // Locked: the window's size alone ends the wait.
  ScriptRun locked = parsed_run("window 600 500\nquit\n");
  step_with_window(locked, st, {1000, 760, 640, 760, true});
  EXPECT_FALSE(locked.quit);
  step_with_window(locked, st, {600, 500, 240, 500, true});
  EXPECT_TRUE(locked.quit);
  EXPECT_EQ(locked.failures, 0);
}

TEST(Script, AWindowSizeTheWindowSystemRefusesFailsAfterItsDeadline) {
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  for (bool sized : {false, true}) {
    ScriptRun run = parsed_run("window 600 500\nquit\n");
    const WindowView view = sized ? WindowView{600, 500, 240, 500, false} : WindowView{1000, 760, 640, 760, true};
    step_with_window(run, st, view);
    step_with_window(run, st, view);
    EXPECT_FALSE(run.quit) << sized;
    run.deadline = std::chrono::steady_clock::now();  // as if 10 s had passed
    step_with_window(run, st, view);
    EXPECT_TRUE(run.quit) << sized;
    EXPECT_EQ(run.failures, 1) << sized;
    EXPECT_FALSE(run.deadline);
  }
}

TEST(Script, WaitsCoverBothSidesOfACompareAndALoadInFlight) {
  // stop-at-spp and wait-frames act on both sides of a compare, whether the stop comes after the compare (side B
  // waits for its time slice, so it cannot pass the stop first) or before it (a compare started later holds it).
  for (const char* script : {"compare sampler=independent\nstop-at-spp 2\nwait-frames 2\n",
                             "stop-at-spp 2\ncompare sampler=independent\nwait-frames 2\n"}) {
    SCOPED_TRACE(script);
    ViewerState st;
    st.init(builtin("cornell"), small_params(), {}, 1);
    st.reference = Image(32, 24);  // each side's fetched frame is measured against it (ViewerState::fetch_frame_b)
    for (float& v : st.reference->rgb) v = 0.5f;
    EXPECT_EQ(run_script(st, script).failures, 0);
    ASSERT_TRUE(st.session_b);
    EXPECT_EQ(st.frame_b.epoch, st.session_b->epoch());
    EXPECT_GE(st.frame_b.frames, 2);
    EXPECT_TRUE(std::isfinite(st.frame_b_rel_mse));
    EXPECT_EQ(st.frame_b_rel_mse, st.rel_mse_to_reference(st.frame_b));
    EXPECT_EQ(st.frame_rel_mse, st.rel_mse_to_reference(st.frame));
    EXPECT_EQ(run_script(st, "wait-ms 100\n").failures, 0);
    st.fetch_frame_b();
    EXPECT_EQ(st.frame_b.frames, 2);
    EXPECT_EQ(st.frame_b.spp, 2);
  }
  TempDir dir;
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  // wait-frames after a load waits for the loaded scene's frames, not the old scene's (which are there: frames of
  // the current epoch, so only the load in flight holds the wait).
  EXPECT_EQ(run_script(st, "compare sampler=independent\nwait-frames 1\n").failures, 0);
  const std::string room = write_two_triangle_light_obj(dir.path);
  EXPECT_EQ(run_script(st, "compare off\nload " + room + "\nwait-frames 1\n").failures, 0);
  EXPECT_EQ(st.scene.source, room);
  EXPECT_GE(st.frame.frames, 1);
}

TEST(Script, PauseOnAndOffHoldAndResumeTheSession) {
  // As the Render panel's checkbox: the state's pause and its session's (under mpirun the workers' too, posted by
  // ViewerState::set_paused: Panels.TheStatsPanelListsEveryRanksSamples).
  ViewerState st;
  st.init(builtin("cornell"), small_params(), {}, 1);
  EXPECT_EQ(run_script(st, "pause on\n").failures, 0);
  EXPECT_TRUE(st.paused);
  EXPECT_TRUE(st.session->paused());
  EXPECT_EQ(run_script(st, "pause off\n").failures, 0);
  EXPECT_FALSE(st.paused);
  EXPECT_FALSE(st.session->paused());
}

TEST(Script, EveryCommandOfTheTableParsesItsWellFormedUse) {
  const char* good =
      "orbit 10 -5\npan 0.1 0\ndolly 0.8\npick 3 4\nset-material glass ior=1.3 emission=0,0,0\nlight 0\n"
      "light-size 0.5 0.2\nlight-scale 1.1\nlight-position 0 1.9 0\nlight-intensity 2\nexposure -1\ntonemap reinhard\n"
      "load x.obj\nwait-frames 2\nwait-spp 4\nwait-ms 10\nstop-at-spp 8\nscreenshot a.png\nsave a.pfm\nsave-scene a.json\nexpect-restart\n"
      "expect-no-restart\ndisplay error\nnoise-threshold 0.05 16\npause on\n"
      "compare integrator=nee sampler=independent light-sampling=area adaptive=0.1\ndivider 0.3\nwindow 800 600\n"
      "quit\n";
  auto r = parse_script(good, "s.txt");
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->size(), script_commands().size());
  for (const ScriptCommandSpec& spec : script_commands()) {
    bool used = false;
    for (const ScriptCommand& c : *r) used |= c.name == spec.name;
    EXPECT_TRUE(used) << spec.name;
  }
}

TEST(Script, TheReadmeListsEveryCommand) {
  std::ifstream in(std::string(PTVIEW_SOURCE_DIR) + "/README.md");
  std::stringstream text;
  text << in.rdbuf();
  for (const ScriptCommandSpec& spec : script_commands())
    EXPECT_NE(text.str().find(std::string("`") + spec.name + (*spec.usage ? " " : "`")), std::string::npos) << spec.name;
}

}  // namespace
}  // namespace pt
