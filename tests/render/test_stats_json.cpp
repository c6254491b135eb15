// The stats JSON (render/stats_json.h) against the run it describes, key by key: the CLI tests check that the keys
// exist and a few values; here every derived value is checked against the counters, the scene and the film, on a
// scene chosen so that the values differ from each other (two spheres but not two lights, bounce rays but not as
// many shadow rays, non-finite samples).
#include <gtest/gtest.h>

#include "render/renderer.h"
#include "render/stats_json.h"
#include "scene_builders.h"

namespace pt {
namespace {

struct StatsRun {
  Scene scene;
  RenderScene rs;
  RenderParams params;
  RunSummary run;
};

/// A mirror sphere beside a sphere of infinite emission, over a diffuse floor under a white background: every
/// material type but glass, a background, bounce and shadow rays, and non-finite samples on the emitter.
StatsRun rendered_run() {
  StatsRun r;
  Scene& s = r.scene;
  s.source = "stats-test";
  const uint32_t floor = test::add_material(s, test::diffuse(vec3(0.5f)));
  const vec3 infinite(std::numeric_limits<float>::infinity());
  const uint32_t emitter = test::add_material(s, test::diffuse(vec3(0.5f), infinite));
  const uint32_t chrome = test::add_material(s, test::mirror(vec3(0.9f)));
  s.background = vec3(1.0f);
  s.spheres.push_back({vec3(-1.2f, 0.0f, 0.0f), 1.0f, emitter});
  s.spheres.push_back({vec3(1.2f, 0.0f, 0.0f), 1.0f, chrome});
  test::add_box(s, vec3(-5.0f, -1.5f, -5.0f), vec3(5.0f, -1.0f, 5.0f), floor, false);
  s.camera = Camera{vec3(0, 1, 6), vec3(0.0f), vec3(0, 1, 0), 60.0f};
  r.rs = make_render_scene(s);
  r.params.width = 24;
  r.params.height = 16;
  r.params.spp_per_frame = 2;
  ProgressiveFilm film;
  film.reset(r.params.width, r.params.height);
  film.set_adaptive({0.05, 0});  // automatic minimum
  Renderer renderer(1);
  for (int f = 0; f < 3; ++f) film.render_frame(renderer, r.rs, r.params, r.run.counters);
  r.run.frames = 3;
  r.run.spp = film.spp();
  r.run.seconds = 2.0;
  r.run.threads = 1;
  r.run.convergence = summarize_convergence(film);
  return r;
}

TEST(StatsJson, EveryDerivedValueIsThatOfTheRun) {
  const StatsRun r = rendered_run();
  const RenderCounters& c = r.run.counters;
  // The scene makes the checks below tell values apart.
  ASSERT_EQ(r.run.spp, 6);
  ASSERT_GT(c.nonfinite_samples, 0u);
  ASSERT_NE(c.bounce_rays, c.shadow_rays);
  ASSERT_NE(r.rs.lights.lights.size(), 2u);

  const nlohmann::json j = make_stats_json(r.params, r.scene, r.rs, r.run);
  EXPECT_EQ(j["scene"], "stats-test");
  EXPECT_EQ(j["frames"], 3);
  EXPECT_EQ(j["spp"], 6);
  EXPECT_DOUBLE_EQ(j["spp_per_s"].get<double>(), 3.0);  // samples per pixel, not frames, per second
  EXPECT_EQ(j["rays"], c.rays());
  EXPECT_DOUBLE_EQ(j["mrays_per_s"].get<double>(), double(c.rays()) / 2.0 * 1e-6);
  EXPECT_EQ(j["samples"], c.samples);
  EXPECT_EQ(j["nonfinite_samples"], c.nonfinite_samples);
  EXPECT_EQ(j["rays_by_kind"]["camera"], c.camera_rays);
  EXPECT_EQ(j["rays_by_kind"]["bounce"], c.bounce_rays);
  EXPECT_EQ(j["rays_by_kind"]["shadow"], c.shadow_rays);
  EXPECT_EQ(j["spheres"], 2);
  EXPECT_EQ(j["lights"], r.rs.lights.lights.size());
  EXPECT_EQ(j["triangles"], 12);
  EXPECT_EQ(j["ranks"], 1);
  // The tree: each key its own figure.
  const TraceGeometry& g = r.rs.trace();
  ASSERT_NE(g.triangles.block_count, g.triangles.node_count);
  EXPECT_EQ(j["bvh"]["primitives"], 14);  // 12 triangles and 2 spheres
  EXPECT_EQ(j["bvh"]["nodes"], g.triangles.node_count + g.sphere_bvh.nodes.size());
  EXPECT_EQ(j["bvh"]["leaf_blocks"], g.triangles.block_count);
  EXPECT_EQ(j["bvh"]["binary_nodes"], g.stats.binary_nodes);
  EXPECT_EQ(j["bvh"]["depth"], g.stats.depth);
  EXPECT_EQ(j["bvh"]["bytes"], g.stats.memory_bytes);
  // Features: the material types in use, by their names, and the background.
  EXPECT_EQ(j["features"]["diffuse"], true);
  EXPECT_EQ(j["features"]["specular"], true);
  EXPECT_EQ(j["features"]["glass"], false);
  EXPECT_EQ(j["features"]["background"], true);
  // Adaptive sampling with the automatic minimum: the minimum in effect, not the 0 that asked for it.
  EXPECT_DOUBLE_EQ(j["noise_threshold"].get<double>(), 0.05);
  EXPECT_EQ(j["min_spp"], auto_min_spp(0.05));
  EXPECT_EQ(j["spp_max"], 6);
}

TEST(StatsJson, WithoutAdaptiveSamplingItsKeysAreAbsent) {
  StatsRun r = rendered_run();
  r.run.convergence.noise_threshold = 0.0;
  const nlohmann::json j = make_stats_json(r.params, r.scene, r.rs, r.run);
  EXPECT_FALSE(j.contains("noise_threshold"));
  EXPECT_FALSE(j.contains("min_spp"));
  r.run.seconds = 0.0;  // no time measured: rates are 0, not inf or NaN
  const nlohmann::json z = make_stats_json(r.params, r.scene, r.rs, r.run);
  EXPECT_EQ(z["spp_per_s"], 0.0);
  EXPECT_EQ(z["mrays_per_s"], 0.0);
}

}  // namespace
}  // namespace pt
