// The integrator against closed-form answers: furnaces, polygon-light irradiance, sphere-light irradiance, and
// agreement of all three strategies. Each test would fail on a biased or wrong estimator.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "render/analytic.h"
#include "render/names.h"
#include "render/renderer.h"
#include "scene/gltf_fixture.h"
#include "scene/load.h"
#include "scene_builders.h"

namespace pt {
namespace {

using test::add_box;
using test::add_material;
using test::diffuse;

struct Estimate {
  double mean = 0.0;
  double stderr_ = 0.0;
};

/// Estimate (channel x) of radiance along the world-space `ray_world`, over n samples.
Estimate estimate(const RenderScene& rs, const RenderParams& params, const Ray& ray_world, int n, uint64_t seed,
                  RenderCounters* counters_out = nullptr) {
  const Ray ray = to_render_frame(rs, ray_world);
  RenderCounters counters;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    PixelSampler sampler = PixelSampler::start(seed, 12345, uint64_t(i), params.sampler);
    vec3 L = trace_path(rs, params, ray, sampler, counters);
    sum += L.x;
    sum2 += double(L.x) * L.x;
  }
  if (counters_out) *counters_out = counters;
  Estimate e;
  e.mean = sum / n;
  double var = std::max(0.0, sum2 / n - e.mean * e.mean);
  e.stderr_ = std::sqrt(var / n);
  return e;
}

const IntegratorKind kIntegrators[] = {IntegratorKind::mis, IntegratorKind::nee, IntegratorKind::bsdf,
                                      IntegratorKind::automatic};
const LightSampling kModes[] = {LightSampling::area, LightSampling::solid_angle, LightSampling::automatic};

/// The parameters of one strategy pair with the given depth, the rest default.
RenderParams strategy(IntegratorKind k, LightSampling mode, int max_depth) {
  RenderParams params;
  params.integrator = k;
  params.light_sampling = mode;
  params.max_depth = max_depth;
  return params;
}

std::string config_name(IntegratorKind k, LightSampling m) {
  return std::string(name_of(k)) + "/" + name_of(m);
}


// ---------------------------------------------------------------------------------------------------------------

TEST(Furnace, WhiteObjectsInUniformBackgroundAreInvisible) {
  // Albedo-1 diffuse, mirror and glass objects under a uniform background of radiance 1: every path carries
  // exactly 1 (glass scales by 1/eta^2 entering and eta^2 leaving), so every pixel is 1.
  Scene s;
  s.background = vec3(1.0f);
  uint32_t white = add_material(s, diffuse(vec3(1.0f)));
  uint32_t m = add_material(s, test::mirror(vec3(1.0f)));
  Material glass;
  glass.type = MaterialType::glass;
  glass.ior = 1.5f;
  uint32_t g = add_material(s, glass);
  s.spheres.push_back({vec3(-1.1f, 0, 0), 0.5f, white});
  s.spheres.push_back({vec3(0, 0, 0), 0.5f, m});
  s.spheres.push_back({vec3(1.1f, 0, 0), 0.5f, g});
  add_box(s, vec3(-0.4f, -1.4f, -0.4f), vec3(0.4f, -0.6f, 0.4f), white, false);  // a closed white cube
  add_box(s, vec3(0.7f, -1.4f, -0.4f), vec3(1.5f, -0.6f, 0.4f), g, false);      // a closed glass cube
  s.camera = Camera{vec3(0, 0, 5), vec3(0, -0.3f, 0), vec3(0, 1, 0), 45.0f};
  RenderScene rs = make_render_scene(s);
  for (IntegratorKind k : kIntegrators) {
    RenderParams params;
    params.width = params.height = 24;
    params.spp_per_frame = 8;
    params.integrator = k;
    params.max_depth = 1000;
    Film film(params.width, params.height);
    Renderer renderer(2);
    RenderCounters counters;
    renderer.render_frame(rs, params, film, 0, counters);
    double max_dev = 0.0;
    for (size_t p = 0; p < film.count.size(); ++p) {
      vec3 v = film.mean(p);
      max_dev = std::max(max_dev, double(max_component(glm::abs(v - vec3(1.0f)))));
    }
    // Paths trapped in glass until roulette are the only variance: allow a little.
    EXPECT_LT(max_dev, 0.02) << config_name(k, LightSampling::solid_angle);
    EXPECT_EQ(counters.nonfinite_samples, 0u);
  }
}

TEST(Furnace, ConvexDiffuseSphereReflectsItsAlbedo) {
  Scene s;
  s.background = vec3(1.0f);
  add_material(s, diffuse(vec3(0.3f, 0.5f, 0.7f)));
  s.spheres.push_back({vec3(0.0f), 1.0f, 0});
  RenderScene rs = make_render_scene(s);
  RenderParams params;
  for (IntegratorKind k : kIntegrators) {
    params.integrator = k;
    RenderCounters c;
    PixelSampler sampler = PixelSampler::start(1, 2, 3);
    for (int i = 0; i < 200; ++i) {
      Ray ray{vec3(0.1f * (i % 7) - 0.3f, 0.05f * (i % 11) - 0.25f, 5.0f), vec3(0, 0, -1), kInfinity};
      vec3 L = trace_path(rs, params, to_render_frame(rs, ray), sampler, c);
      // A convex object cannot see itself: one bounce, then the background; exact.
      EXPECT_NEAR(L.x, 0.3f, 1e-5f);
      EXPECT_NEAR(L.y, 0.5f, 1e-5f);
      EXPECT_NEAR(L.z, 0.7f, 1e-5f);
    }
  }
}

TEST(Furnace, ClosedEmissiveRoomConvergesToGeometricSeries) {
  // Inside a closed box whose walls emit Le (front faces inward) with albedo a, radiance is Le / (1 - a)
  // everywhere: an infinite-bounce answer that needs roulette and counts emission exactly once per path.
  const float a = 0.6f, le = 0.4f;  // expected radiance 1
  Scene s;
  add_material(s, diffuse(vec3(a), vec3(le)));
  add_box(s, vec3(-1.0f), vec3(1.0f), 0, true);
  RenderScene rs = make_render_scene(s);
  ASSERT_EQ(rs.lights.lights.size(), 6u);
  for (IntegratorKind k : kIntegrators)
    for (LightSampling mode : kModes) {
      const RenderParams params = strategy(k, mode, 1000);
      Ray ray{vec3(0.1f, 0.2f, 0.3f), glm::normalize(vec3(0.3f, -0.5f, 0.8f)), kInfinity};
      Estimate e = estimate(rs, params, ray, 40000, 7);
      EXPECT_NEAR(e.mean, 1.0, 5.0 * e.stderr_ + 1e-3) << config_name(k, mode);
    }
}

TEST(Furnace, HighAlbedoRoomKeepsTheTailRouletteDecides) {
  // With albedo 0.9 the throughput falls below Russian roulette's threshold after about ten bounces, and from there
  // every vertex is rouletted (survival about 0.9): about a third of the answer comes from paths roulette decides,
  // so a survivor's weight off by 1% moves the mean by about 3%. (In the albedo-0.6 room above roulette decides a
  // fifth of the answer over about two vertices, and the same error moves it by 0.5%: within that test's noise.)
  const float a = 0.9f, le = 0.1f;  // expected radiance le / (1 - a) = 1
  Scene s;
  add_material(s, diffuse(vec3(a), vec3(le)));
  add_box(s, vec3(-1.0f), vec3(1.0f), 0, true);
  RenderScene rs = make_render_scene(s);
  for (IntegratorKind k : {IntegratorKind::mis, IntegratorKind::bsdf}) {
    RenderParams params;
    params.integrator = k;
    params.max_depth = 100000;
    const Ray ray{vec3(0.1f, 0.2f, 0.3f), glm::normalize(vec3(0.3f, -0.5f, 0.8f)), kInfinity};
    RenderCounters counters;
    const Estimate e = estimate(rs, params, ray, 100000, 11, &counters);
    EXPECT_NEAR(e.mean, 1.0, 5.0 * e.stderr_ + 1e-3) << name_of(k);
    EXPECT_EQ(counters.paths_ended_max_depth, 0u);
  }
}

// ---------------------------------------------------------------------------------------------------------------

struct LightOverPlane {
  RenderScene rs;
  std::vector<dvec3> light_polygon;
  float albedo = 0.5f;
  float radiance = 4.0f;
};

/// The "rect" set-up as a glTF file, loaded by load_scene: the floor and an emissive quad (two triangles, emission
/// emissiveFactor x KHR_materials_emissive_strength), each placed by a node translation.
LightOverPlane make_gltf_light_over_plane() {
  LightOverPlane out;
  test::GltfBuilder b;
  int floor_mat = b.material({{"pbrMetallicRoughness", {{"baseColorFactor", {out.albedo, out.albedo, out.albedo, 1}},
                                                        {"metallicFactor", 0}, {"roughnessFactor", 1}}}});
  int lamp_mat = b.material({{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
                             {"emissiveFactor", {1, 1, 1}},
                             {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", out.radiance}}}}}});
  std::vector<vec3> floor = {{-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}};  // counter-clockwise from above
  vec3 c(-0.3f, 0.0f, -0.2f), e1(0.8f, 0, 0), e2(0, 0, 0.5f);  // cross(e1, e2) = -y: faces down
  std::vector<vec3> lamp = {c, c + e1, c + e1 + e2, c + e2};
  std::vector<uint8_t> quad = {0, 1, 2, 0, 2, 3};
  b.node({{"mesh", b.mesh(b.positions(floor), b.indices(quad), floor_mat)}, {"translation", {0, -2, 0}}});
  b.node({{"mesh", b.mesh(b.positions(lamp), b.indices(quad), lamp_mat)}, {"translation", {0, -1, 0}}});
  b.j["scenes"][0]["nodes"] = {2};
  b.node({{"children", {0, 1}}, {"translation", {0, 2, 0}}}, false);  // floor at y = 0, lamp at y = 1
  std::string path = (std::filesystem::temp_directory_path() / ("ptview-light-" + std::to_string(::getpid()) + ".glb")).string();
  test::write_file(path, b.glb());
  Result<Scene> s = load_scene(path);
  std::filesystem::remove(path);
  EXPECT_TRUE(s.ok()) << s.error();
  if (!s.ok()) return out;
  for (vec3 p : lamp) out.light_polygon.push_back(dvec3(p + vec3(0, 1, 0)));
  out.rs = make_render_scene(*s);
  return out;
}

/// A large diffuse floor at y = 0 facing up and an emitter 1 unit above it, facing down.
LightOverPlane make_light_over_plane(const std::string& kind) {
  if (kind == "gltf-quad") return make_gltf_light_over_plane();
  LightOverPlane out;
  Scene s;
  add_material(s, diffuse(vec3(out.albedo)));
  uint32_t emitter = add_material(s, diffuse(vec3(0.0f), vec3(out.radiance)));
  s.quads.push_back({vec3(-50, 0, 50), vec3(100, 0, 0), vec3(0, 0, -100), 0});
  if (kind == "rect" || kind == "parallelogram") {
    // cross(e1, e2) = -y: faces down. The parallelogram is sheared by 45 degrees: two spherical triangles.
    vec3 c(-0.3f, 1.0f, -0.2f), e1(0.8f, 0, 0), e2 = kind == "rect" ? vec3(0, 0, 0.5f) : vec3(0.5f, 0, 0.5f);
    s.quads.push_back({c, e1, e2, emitter});
    out.light_polygon = {dvec3(c), dvec3(c + e1), dvec3(c + e1 + e2), dvec3(c + e2)};
  } else if (kind == "quad-apart") {
    // A quad's two triangles with a third, non-emissive one between them in the mesh (below the floor, out of
    // sight): they still merge into one rectangle light (render/emissive_pairs.h), whose pdf hits on either
    // triangle must get.
    Mesh mesh;
    vec3 c(-0.3f, 1.0f, -0.2f), e1(0.8f, 0, 0), e2(0, 0, 0.5f);
    mesh.positions = {c, c + e1, c + e1 + e2, c + e2, vec3(40, -1, 40), vec3(41, -1, 40), vec3(40, -1, 41)};
    mesh.indices = {uvec3(2, 3, 0), uvec3(4, 5, 6), uvec3(0, 1, 2)};  // CCW seen from below: faces down
    mesh.materials = {emitter, 0, emitter};
    out.light_polygon = {dvec3(c), dvec3(c + e1), dvec3(c + e1 + e2), dvec3(c + e2)};
    s.meshes.push_back(mesh);
  } else {  // an emissive mesh triangle
    Mesh mesh;
    mesh.positions = {vec3(-0.4f, 1.0f, -0.3f), vec3(0.5f, 1.0f, -0.2f), vec3(0.0f, 1.0f, 0.6f)};
    mesh.indices = {uvec3(0, 1, 2)};  // CCW seen from below: faces down
    mesh.materials = {emitter};
    for (vec3 p : mesh.positions) out.light_polygon.push_back(dvec3(p));
    s.meshes.push_back(mesh);
  }
  out.rs = make_render_scene(s);
  return out;
}

class PolygonIrradiance : public ::testing::TestWithParam<std::string> {};

TEST_P(PolygonIrradiance, DirectLightingMatchesLambertsFormula) {
  LightOverPlane setup = make_light_over_plane(GetParam());
  if (GetParam() == "gltf-quad") {
    ASSERT_GE(setup.rs.lights.lights.size(), 1u);  // two triangles, or one merged quad
  } else {
    ASSERT_EQ(setup.rs.lights.lights.size(), 1u);
    if (GetParam() == "quad-apart") {
      ASSERT_TRUE(setup.rs.lights.lights[0].rectangular);
    }
  }
  const vec3 points[] = {vec3(0.05f, 0, 0.02f), vec3(0.9f, 0, -0.7f), vec3(-2.0f, 0, 1.5f)};
  for (vec3 x : points) {
    double expected = setup.albedo / M_PI *
                      polygon_irradiance(setup.light_polygon, dvec3(x), dvec3(0, 1, 0), setup.radiance);
    for (IntegratorKind k : kIntegrators)
      for (LightSampling mode : kModes) {
        RenderParams params;
        params.integrator = k;
        params.light_sampling = mode;
        params.max_depth = 1;  // emission seen directly + direct lighting at the first hit
        Ray ray{x + vec3(0.0f, 0.5f, 0.0f), vec3(0, -1, 0), kInfinity};
        // automatic under both of its per-scene choices at the first vertex (render/auto_light_sampling.h): MIS
        // must weigh with the threshold the light sample was drawn with.
        for (float first_spread : {kAutoMinSpread, kAutoMinSpreadDeep}) {
          if (mode != LightSampling::automatic && first_spread != kAutoMinSpread) continue;
          setup.rs.auto_first_spread = first_spread;
          for (SamplerKind sampler : {SamplerKind::independent, SamplerKind::sobol}) {
            params.sampler = sampler;
            // For Sobol the sample variance overstates the error: the bound stays valid, only looser.
            Estimate e = estimate(setup.rs, params, ray, 60000, 11);
            EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-4 * expected)
                << GetParam() << " " << config_name(k, mode) << " first spread " << first_spread << " sampler "
                << int(sampler) << " at x=" << x.x << "," << x.z;
          }
        }
      }
  }
}
INSTANTIATE_TEST_SUITE_P(Lights, PolygonIrradiance,
                         ::testing::Values("rect", "parallelogram", "triangle", "quad-apart", "gltf-quad"));

/// A diffuse floor at y = 0 (albedo kFloorAlbedo, material 0) under a 2 x 2 light of radiance kSquareRadiance at
/// y = 1, facing down and centred over the origin (material 1, its corners kSquareLight). Seen from the origin its
/// area density spreads by (sqrt(3) / 1)^3 = 5.2, between the two automatic thresholds. Tests add their shapes.
constexpr float kFloorAlbedo = 0.5f, kSquareRadiance = 4.0f;
const std::vector<dvec3> kSquareLight = {dvec3(-1, 1, -1), dvec3(1, 1, -1), dvec3(1, 1, 1), dvec3(-1, 1, 1)};
Scene square_light_over_floor() {
  Scene s;
  add_material(s, diffuse(vec3(kFloorAlbedo)));
  const uint32_t emitter = add_material(s, diffuse(vec3(0.0f), vec3(kSquareRadiance)));
  s.quads.push_back({vec3(-50, 0, 50), vec3(100, 0, 0), vec3(0, 0, -100), 0});
  s.quads.push_back({vec3(-1.0f, 1.0f, -1.0f), vec3(2, 0, 0), vec3(0, 0, 2), emitter});  // cross = -y: faces down
  return s;
}

TEST(PolygonIrradianceMis, FirstVertexThresholdIsTheOneTheLightSampleUsed) {
  // MIS under automatic light sampling weighs an emitter hit with light_pdf at the previous vertex, which must use
  // the same spread threshold as that vertex's light sample (1.5 or 8 at the first vertex, per scene). In the
  // light-over-plane scenes above a BSDF sample rarely hits the light, so a mismatched threshold moved the estimate
  // by about 0.2%, under their bound. Here a 2 x 2 light 1 above the receiver: its area density spreads by
  // (sqrt(3) / 1)^3 = 5.2, between the two thresholds, so the thresholds choose different samplings, and it fills
  // a third of the cosine-weighted hemisphere, so the BSDF side carries real weight.
  RenderScene rs = make_render_scene(square_light_over_floor());
  const vec3 x(0.0f);
  const double expected =
      kFloorAlbedo / M_PI * polygon_irradiance(kSquareLight, dvec3(x), dvec3(0, 1, 0), kSquareRadiance);
  RenderParams params;
  params.integrator = IntegratorKind::mis;
  params.light_sampling = LightSampling::automatic;
  params.max_depth = 1;
  const Ray ray{x + vec3(0.0f, 0.5f, 0.0f), vec3(0, -1, 0), kInfinity};
  for (float first_spread : {kAutoMinSpread, kAutoMinSpreadDeep}) {
    rs.auto_first_spread = first_spread;
    const Estimate e = estimate(rs, params, ray, 200000, 17);
    EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-4 * expected) << "first spread " << first_spread;
  }
}

TEST(Shadows, AnOccluderHidesItsPartOfTheLight) {
  // A black quad half-way between the floor and a 2 x 2 light covers the light's x > 0 half as seen from the origin
  // (its edge is on the line from the origin to the light's middle): the origin's irradiance is that of the other
  // half alone, Lambert's formula for the rectangle [-1, 0] x [-1, 1]. Every strategy must see the shadow: light
  // samples behind the quad are blocked, BSDF samples toward them hit it.
  Scene s = square_light_over_floor();
  const uint32_t black = add_material(s, diffuse(vec3(0.0f)));
  s.quads.push_back({vec3(0.0f, 0.5f, -5.0f), vec3(5, 0, 0), vec3(0, 0, 10), black});
  RenderScene rs = make_render_scene(s);
  const std::vector<dvec3> visible = {dvec3(-1, 1, -1), dvec3(0, 1, -1), dvec3(0, 1, 1), dvec3(-1, 1, 1)};
  const double expected =
      kFloorAlbedo / M_PI * polygon_irradiance(visible, dvec3(0.0), dvec3(0, 1, 0), kSquareRadiance);
  const Ray ray{vec3(0.0f, 0.25f, 0.0f), vec3(0, -1, 0), kInfinity};
  for (IntegratorKind k : kIntegrators)
    for (LightSampling mode : kModes) {
      const Estimate e = estimate(rs, strategy(k, mode, 1), ray, 60000, 31);
      EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-4 * expected) << config_name(k, mode);
    }
}

TEST(Mirrors, ALightSeenInAMirrorKeepsItsRadiance) {
  // Camera -> albedo-1 mirror -> light: the emission reaches the camera in full under every strategy. Light
  // sampling skips the mirror vertex, so the emitter hit after it is the only way this light is counted (its MIS
  // weight is 1).
  Scene s;
  const float radiance = 4.0f;
  const uint32_t emitter = add_material(s, diffuse(vec3(0.0f), vec3(radiance)));
  const uint32_t m = add_material(s, test::mirror(vec3(1.0f)));
  s.quads.push_back({vec3(-1.0f, 1.0f, -1.0f), vec3(2, 0, 0), vec3(0, 0, 2), emitter});  // y = 1, faces down
  s.quads.push_back({vec3(-5, 0, 5), vec3(10, 0, 0), vec3(0, 0, -10), m});             // y = 0, faces up
  RenderScene rs = make_render_scene(s);
  // Down onto the mirror at (-0.5, 0, 0), up to the light at (0.5, 1, 0).
  const Ray ray{vec3(-1.0f, 0.5f, 0.0f), glm::normalize(vec3(1.0f, -1.0f, 0.0f)), kInfinity};
  for (IntegratorKind k : kIntegrators)
    for (LightSampling mode : kModes)
      for (int depth : {1, 3}) {
        const Estimate e = estimate(rs, strategy(k, mode, depth), ray, 1000, 37);
        EXPECT_NEAR(e.mean, radiance, 1e-5 * radiance) << config_name(k, mode) << " depth " << depth;
      }
}

TEST(PolygonIrradianceMis, AMirrorPassesTheFirstVertexsLightSamplingOn) {
  // The first non-delta vertex takes the scene's spread threshold whether the camera sees it directly or through a
  // mirror (integrator.cpp, VertexLightSampling). The light and receiver of the test above, where the two thresholds
  // choose different samplings (solid angle at 1.5, area at 8) whose estimates differ in variance; the receiver's
  // direct light seen straight down, and seen in a vertical albedo-1 mirror off to the side: a Lambertian receiver
  // reflects the same whatever the direction it is seen from, so the two estimates have the same mean and, if the
  // mirror path samples the light the same way, the same variance.
  Scene s = square_light_over_floor();
  const uint32_t m = add_material(s, test::mirror(vec3(1.0f)));
  s.quads.push_back({vec3(3.0f, 0.5f, -2.0f), vec3(0, 0, 4), vec3(0, 2.5f, 0), m});     // x = 3, faces -x
  RenderScene rs = make_render_scene(s);
  RenderParams params = strategy(IntegratorKind::nee, LightSampling::automatic, 1);
  // Straight down onto (0, 0, 0); and toward the mirror at (3, 1.5, 0), which reflects the ray onto (0, 0, 0).
  const Ray direct{vec3(0.0f, 0.5f, 0.0f), vec3(0, -1, 0), kInfinity};
  const Ray via_mirror{vec3(1.5f, 2.25f, 0.0f), glm::normalize(vec3(3.0f, -1.5f, 0.0f)), kInfinity};
  double stderr_of[2][2];  // [threshold][direct, via mirror]
  const float thresholds[2] = {kAutoMinSpread, kAutoMinSpreadDeep};
  for (int t = 0; t < 2; ++t) {
    rs.auto_first_spread = thresholds[t];
    params.max_depth = 1;
    const Estimate d = estimate(rs, params, direct, 200000, 23);
    params.max_depth = 2;
    const Estimate v = estimate(rs, params, via_mirror, 200000, 29);
    EXPECT_NEAR(v.mean, d.mean, 5.0 * std::hypot(d.stderr_, v.stderr_)) << "threshold " << thresholds[t];
    stderr_of[t][0] = d.stderr_;
    stderr_of[t][1] = v.stderr_;
  }
  // The two samplings must differ for the test to mean anything; then each threshold's two views agree.
  EXPECT_GT(stderr_of[1][0], 1.2 * stderr_of[0][0]);
  for (int t = 0; t < 2; ++t)
    EXPECT_NEAR(stderr_of[t][1] / stderr_of[t][0], 1.0, 0.05)
        << "threshold " << thresholds[t] << ": direct " << stderr_of[t][0] << ", via the mirror " << stderr_of[t][1];
}

TEST(SphereLight, IrradianceBelowASphereMatchesClosedForm) {
  // A sphere of radiance L and radius r whose center is at distance d straight above x: E = pi L (r/d)^2.
  Scene s;
  add_material(s, diffuse(vec3(1.0f)));
  uint32_t emitter = add_material(s, diffuse(vec3(0.0f), vec3(2.0f)));
  s.quads.push_back({vec3(-50, 0, 50), vec3(100, 0, 0), vec3(0, 0, -100), 0});
  const float r = 0.3f, d = 1.5f;
  s.spheres.push_back({vec3(0, d, 0), r, emitter});
  RenderScene rs = make_render_scene(s);
  double expected = 1.0 / M_PI * sphere_irradiance(dvec3(0, d, 0), r, dvec3(0.0), dvec3(0, 1, 0), 2.0);
  for (IntegratorKind k : kIntegrators) {
    RenderParams params;
    params.integrator = k;
    params.max_depth = 1;
    Ray ray{vec3(0, 0.5f, 0), vec3(0, -1, 0), kInfinity};
    Estimate e = estimate(rs, params, ray, 60000, 5);
    EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-4) << config_name(k, LightSampling::solid_angle);
  }
}

TEST(LightPdf, SampleAndPdfAgreeForEveryLightKind) {
  // MIS is only unbiased if light_pdf returns the density sample_light used. Every light faces the box its
  // reference points are drawn from, and every (light, mode) pair must be checked often; the small and the large
  // rectangles and triangles are placed so that their solid angle crosses the solid-angle/area switch (3e-4 and
  // 6.22 sr) inside the box, and both sides of the switch must be seen.
  struct Case {
    const char* name;
    Light light;
    vec3 box_min, box_max;  ///< reference points, uniform in this box
    float switch_at;        ///< a solid-angle threshold this case must cross (0: none)
  };
  const Case cases[] = {
      {"rectangle", make_rect_light(vec3(-0.5f, 1, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1), vec3(1)), vec3(-2, -0.5f, -2),
       vec3(2, 0.9f, 2), 0.0f},
      {"parallelogram", make_rect_light(vec3(-0.5f, 1, -0.5f), vec3(1, 0, 0), vec3(0.2f, 0, 1), vec3(1)),
       vec3(-2, -0.5f, -2), vec3(2, 0.9f, 2), 0.0f},
      {"small rectangle", make_rect_light(vec3(-0.01f, 1, -0.01f), vec3(0.02f, 0, 0), vec3(0, 0, 0.02f), vec3(1)),
       vec3(-0.3f, -0.5f, -0.3f), vec3(0.3f, 0.5f, 0.3f), 3e-4f},
      {"large rectangle", make_rect_light(vec3(-20, 1, -20), vec3(40, 0, 0), vec3(0, 0, 40), vec3(1)),
       vec3(-1, 0.0f, -1), vec3(1, 0.9999f, 1), 6.22f},
      {"triangle", make_triangle_light(vec3(-0.5f, 1, -0.5f), vec3(0.5f, 1, -0.5f), vec3(0, 1, 0.7f), vec3(1)),
       vec3(-2, -0.5f, -2), vec3(2, 0.9f, 2), 0.0f},
      {"small triangle",
       make_triangle_light(vec3(-0.01f, 1, -0.01f), vec3(0.01f, 1, -0.01f), vec3(-0.01f, 1, 0.01f), vec3(1)),
       vec3(-0.3f, -0.5f, -0.3f), vec3(0.3f, 0.5f, 0.3f), 3e-4f},
      {"large triangle", make_triangle_light(vec3(-20, 1, -20), vec3(60, 1, -20), vec3(-20, 1, 60), vec3(1)),
       vec3(-1, 0.0f, -1), vec3(1, 0.9999f, 1), 6.22f},
      {"sphere", make_sphere_light(vec3(0, 1.5f, 0), 0.4f, vec3(1)), vec3(-2, -0.5f, -2), vec3(2, 0.9f, 2), 0.0f},
      {"tiny sphere", make_sphere_light(vec3(0, 400.0f, 0), 0.01f, vec3(1)), vec3(-2, -0.5f, -2), vec3(2, 0.9f, 2),
       0.0f},
  };
  Pcg32 rng(3, 4);
  for (const Case& c : cases)
    for (LightSampling mode : kModes) {
      int checked = 0, below = 0, above = 0;
      for (int i = 0; i < 2000; ++i) {
        vec3 t(rng.next_float(), rng.next_float(), rng.next_float());
        vec3 ref = c.box_min + t * (c.box_max - c.box_min);
        LightSample ls;
        if (!sample_light(c.light, ref, vec2(rng.next_float(), rng.next_float()), mode, ls)) continue;
        vec3 n_light = c.light.kind == LightKind::sphere ? glm::normalize(ls.point.p - c.light.p0) : c.light.n;
        float pdf = light_pdf(c.light, ref, ls.wi, ls.dist, n_light, mode);
        ASSERT_NEAR(pdf, ls.pdf, 2e-3f * ls.pdf) << c.name << " mode " << int(mode) << " ref " << ref.x << ","
                                                 << ref.y << "," << ref.z;
        ++checked;
        if (c.switch_at > 0.0f) {
          SphericalRectangle sr;
          SphericalTriangle st;
          if (c.light.kind == LightKind::triangle) make_spherical_triangle(ref, c.light.p0, c.light.e1, c.light.e2, st);
          else make_spherical_rectangle(ref, c.light.p0, c.light.e1, c.light.e2, sr);
          float solid_angle = c.light.kind == LightKind::triangle ? st.solid_angle : sr.solid_angle;
          (solid_angle < c.switch_at ? below : above)++;
        }
      }
      EXPECT_GE(checked, 1000) << c.name << " mode " << int(mode);
      if (c.switch_at > 0.0f) {
        EXPECT_GE(below, 100) << c.name << ": the switch at " << c.switch_at << " sr is not crossed";
        EXPECT_GE(above, 100) << c.name << ": the switch at " << c.switch_at << " sr is not crossed";
      }
    }
}

// ---------------------------------------------------------------------------------------------------------------

TEST(Strategies, AllThreeConvergeToTheSameImage) {
  Scene s = test::make_test_cornell();
  RenderScene rs = make_render_scene(s);
  RenderParams base;
  base.max_depth = 6;
  // A few pixels looking at the floor, a wall, the glass and the mirror sphere.
  const Ray rays[] = {
      {vec3(0, 1, 0.99f), glm::normalize(vec3(0.1f, -0.8f, -0.5f)), kInfinity},
      {vec3(0, 1, 0.99f), glm::normalize(vec3(-0.9f, 0.1f, -0.6f)), kInfinity},
      {vec3(0, 1, 0.99f), glm::normalize(vec3(-0.45f, -0.6f, -1.0f)), kInfinity},
      {vec3(0, 1, 0.99f), glm::normalize(vec3(0.45f, -0.6f, -1.3f)), kInfinity},
  };
  for (const Ray& ray : rays) {
    RenderParams mis = base;
    mis.integrator = IntegratorKind::mis;
    Estimate reference = estimate(rs, mis, ray, 60000, 21);
    for (IntegratorKind k : kIntegrators)
      for (LightSampling mode : kModes) {
        RenderParams p = base;
        p.integrator = k;
        p.light_sampling = mode;
        Estimate e = estimate(rs, p, ray, 60000, 99);
        double sigma = std::sqrt(e.stderr_ * e.stderr_ + reference.stderr_ * reference.stderr_);
        EXPECT_NEAR(e.mean, reference.mean, 5.0 * sigma + 1e-4) << config_name(k, mode);
      }
  }
}

TEST(MaxDepth, ZeroSeesOnlyEmissionDirectly) {
  Scene s = test::make_test_cornell();
  RenderScene rs = make_render_scene(s);
  RenderParams p;
  p.max_depth = 0;
  RenderCounters c;
  PixelSampler sampler = PixelSampler::start(0, 0, 0);
  Ray at_wall{vec3(0, 1, 0.99f), vec3(0, 0, -1), kInfinity};
  EXPECT_EQ(trace_path(rs, p, to_render_frame(rs, at_wall), sampler, c), vec3(0.0f));
  Ray at_light{vec3(0, 1, 0.0f), vec3(0, 1, 0), kInfinity};
  EXPECT_EQ(trace_path(rs, p, to_render_frame(rs, at_light), sampler, c), vec3(15.0f, 12.0f, 8.0f));
  EXPECT_EQ(c.shadow_rays, 0u);
}

/// A sphere emitting `emission` against a white background: every camera ray that sees it carries that radiance,
/// and the pixels on its outline get samples of both kinds.
RenderScene emitter_scene(vec3 emission) {
  Scene s;
  add_material(s, diffuse(vec3(0.5f), emission));
  s.background = vec3(1.0f);
  s.spheres.push_back({vec3(0.0f), 1.0f, 0});
  s.camera = Camera{vec3(0, 0, 3), vec3(0.0f), vec3(0, 1, 0), 60.0f};
  return make_render_scene(s);
}

/// The emitter above with infinite radiance: non-finite samples where the sphere is seen.
RenderScene infinite_emitter_scene() { return emitter_scene(vec3(std::numeric_limits<float>::infinity())); }

/// One 8 x 8 frame of one sample a pixel of `rs`, which must give some samples to drop and some to keep: the
/// dropped ones are counted, and they and the kept ones make up every sample.
Film expect_some_dropped(const RenderScene& rs) {
  RenderParams params;
  params.width = params.height = 8;
  Film film(8, 8);
  Renderer renderer(1);
  RenderCounters c;
  renderer.render_frame(rs, params, film, 0, c);
  EXPECT_GT(c.nonfinite_samples, 0u);
  EXPECT_LT(c.nonfinite_samples, 64u);
  size_t counted = 0;
  for (uint32_t n : film.count) counted += n;
  EXPECT_EQ(counted + c.nonfinite_samples, 64u);
  return film;
}

TEST(NonFinite, SamplesAreDroppedAndCounted) {
  const Film film = expect_some_dropped(infinite_emitter_scene());
  for (size_t p = 0; p < film.count.size(); ++p) EXPECT_TRUE(is_finite(film.mean(p)));
}

// Radiance is never negative; a sample that is (a scene built in code with a negative emission, which the loaders
// refuse) is dropped and counted as the non-finite ones are, never averaged in.
TEST(NonFinite, NegativeSamplesAreDroppedAndCountedToo) {
  const Film film = expect_some_dropped(emitter_scene(vec3(-2.0f, 1.0f, 1.0f)));
  for (double v : film.sum) EXPECT_GE(v, 0.0);
}

// A dropped sample still takes its index: the adaptive passes (Renderer::render_pass, which continue each pixel at
// the samples it has drawn) give the film of frames 0..n-1 bit for bit, dropped samples and all. Continuing at the
// count of kept samples instead would draw a dropped sample's index again, and get the same non-finite sample.
TEST(NonFinite, PassesDrawTheIndexAfterADroppedSample) {
  RenderScene rs = infinite_emitter_scene();
  RenderParams params;
  params.width = params.height = 8;
  params.spp_per_frame = 1;
  Renderer renderer(1);
  Film frames(8, 8), passes(8, 8);
  RenderCounters by_frame, by_pass;
  for (uint32_t k = 0; k < 16; ++k) {
    renderer.render_frame(rs, params, frames, k, by_frame);
    renderer.render_pass(rs, params, passes, nullptr, by_pass);
  }
  ASSERT_GT(by_frame.nonfinite_samples, 0u);
  EXPECT_EQ(by_pass.nonfinite_samples, by_frame.nonfinite_samples);
  EXPECT_EQ(passes.count, frames.count);
  EXPECT_EQ(passes.sum, frames.sum);
  EXPECT_EQ(passes.taken, std::vector<uint32_t>(64, 16u));
}

// The automatic integrator is MIS only where lights are sampled by area: there BSDF sampling covers what area
// sampling does badly (a light seen at a grazing angle or from close by). Solid-angle sampling (the automatic mode
// uses it at the first vertex) has no such weakness, and NEE skips MIS's second light pdf per hit.
TEST(Integrators, AutomaticResolvesToMisOnlyUnderAreaSampling) {
  EXPECT_EQ(resolve_integrator(IntegratorKind::automatic, LightSampling::area), IntegratorKind::mis);
  EXPECT_EQ(resolve_integrator(IntegratorKind::automatic, LightSampling::solid_angle), IntegratorKind::nee);
  EXPECT_EQ(resolve_integrator(IntegratorKind::automatic, LightSampling::automatic), IntegratorKind::nee);
  for (IntegratorKind k : {IntegratorKind::mis, IntegratorKind::nee, IntegratorKind::bsdf})
    for (LightSampling m : kModes) EXPECT_EQ(resolve_integrator(k, m), k) << config_name(k, m);
}

/// The counters of two frames of 24 x 24 pixels, depth 6 (deep enough that some paths reach the limit).
RenderCounters count_two_frames(Renderer& renderer, const RenderScene& rs, IntegratorKind k) {
  RenderParams p;
  p.width = p.height = 24;
  p.max_depth = 6;
  p.integrator = k;
  Film film(p.width, p.height);
  RenderCounters c;
  for (uint32_t f = 0; f < 2; ++f) renderer.render_frame(rs, p, film, f, c);
  return c;
}

// The counters account for every path vertex: each closest-hit ray either escapes, ends the path at the maximum
// depth, or reaches a surface that samples the lights (a shadow ray, or one of the reasons none was cast) or skips
// light sampling because it is a mirror or glass. Under BSDF sampling nothing samples lights.
TEST(Counters, EveryVertexIsAccountedFor) {
  Renderer renderer(2);
  for (bool delta : {true, false}) {
    Scene s = test::make_test_cornell();
    if (!delta) test::make_diffuse_only(s, vec3(0.6f, 0.5f, 0.4f));
    const RenderScene rs = make_render_scene(s);
    ASSERT_EQ(rs.features.has_delta, delta);
    for (IntegratorKind k : kIntegrators) {
      const RenderCounters c = count_two_frames(renderer, rs, k);
      const std::string what = std::string(name_of(k)) + (delta ? " with mirrors and glass" : " diffuse only");
      const uint64_t hits = c.camera_rays + c.bounce_rays - c.paths_escaped - c.paths_ended_max_depth;
      const uint64_t light_sampled = c.shadow_rays + c.shadow_skipped_backfacing + c.shadow_skipped_zero_bsdf;
      EXPECT_GT(c.paths_ended_max_depth, 0u) << what;
      if (k == IntegratorKind::bsdf) {
        EXPECT_EQ(light_sampled + c.light_sampling_skipped_specular, 0u) << what;
        continue;
      }
      EXPECT_EQ(light_sampled + c.light_sampling_skipped_specular, hits) << what;
      EXPECT_GT(light_sampled, 0u) << what;
      if (delta) {
        EXPECT_GT(c.light_sampling_skipped_specular, 0u) << what;
      } else {
        EXPECT_EQ(c.light_sampling_skipped_specular, 0u) << what;
      }
    }
  }
}

// Every path ends for exactly one counted reason: it escapes, reaches the maximum depth, is ended by roulette, or
// is absorbed (the BSDF sample failed or left no throughput). A black wall absorbs every path that reaches it; on a
// pyramid whose smooth shading normals lean up to 73 degrees from its faces many bounces fall below the surface.
TEST(Counters, EveryPathEndsForOneCountedReason) {
  Renderer renderer(2);
  for (int variant = 0; variant < 4; ++variant) {
    Scene s = test::make_test_cornell();
    if (variant == 1) test::make_diffuse_only(s, vec3(0.6f, 0.5f, 0.4f));
    if (variant == 2) {
      const auto wall = std::find_if(s.materials.begin(), s.materials.end(), [](const Material& m) {
        return m.type == MaterialType::diffuse && !m.emissive();
      });
      ASSERT_NE(wall, s.materials.end());
      wall->albedo = vec3(0.0f);
    }
    if (variant == 3) {
      Mesh pyramid;  // on the floor, apex up, faces outward
      pyramid.positions = {vec3(-0.3f, 0, -0.1f), vec3(0.3f, 0, -0.1f), vec3(0.3f, 0, -0.7f), vec3(-0.3f, 0, -0.7f),
                           vec3(0, 0.3f, -0.4f)};
      pyramid.indices = {uvec3(0, 1, 4), uvec3(1, 2, 4), uvec3(2, 3, 4), uvec3(3, 0, 4)};
      for (vec3 q : pyramid.positions) pyramid.normals.push_back(glm::normalize(q - vec3(0, 0.12f, -0.4f)));
      pyramid.normal_indices = pyramid.indices;
      pyramid.materials.assign(pyramid.indices.size(), 0);
      s.meshes.push_back(pyramid);
    }
    const RenderScene rs = make_render_scene(s);
    for (IntegratorKind k : kIntegrators) {
      const RenderCounters c = count_two_frames(renderer, rs, k);
      const std::string what = std::string(name_of(k)) + " variant " + std::to_string(variant);
      EXPECT_EQ(c.samples, uint64_t(2 * 24 * 24)) << what;
      EXPECT_EQ(c.paths_escaped + c.paths_ended_max_depth + c.paths_ended_roulette + c.paths_ended_absorbed, c.samples)
          << what;
      EXPECT_GT(c.paths_ended_absorbed, 0u) << what;  // at least the paths that reach the light (albedo 0)
      if (variant != 2) {
        EXPECT_GT(c.paths_ended_roulette, 0u) << what;  // the white walls are black in variant 2
      }
    }
  }
}

/// RenderScene::tri_unlit_sides only skips light samples that add nothing: the same scene renders bit-identically
/// with the marks cleared, with the same counters. A box in the room has sides facing away from the light (marked),
/// and the room's walls are marked on their outer sides only.
TEST(UnlitSides, SkippingThemChangesNothing) {
  Scene s = test::make_test_cornell();
  add_box(s, vec3(-0.7f, 0, 0.1f), vec3(-0.3f, 1.2f, 0.6f), 0, false);
  const RenderScene rs = make_render_scene(s);
  RenderScene cleared = rs;
  std::fill(cleared.tri_unlit_sides.begin(), cleared.tri_unlit_sides.end(), uint8_t(0));
  int front_unlit = 0;
  for (uint32_t t = 0; t < rs.triangle_count(); ++t) {
    const uint32_t quad = (t - rs.geo->quad_first_triangle) / 2;
    if (quad < 6) {
      EXPECT_EQ(rs.tri_unlit_sides[t], 2) << "room wall " << quad;  // lit inside, unlit outside
    } else if (quad == 6) {
      EXPECT_EQ(rs.tri_unlit_sides[t], 0) << "the light";  // in its own plane
    }
    front_unlit += rs.tri_unlit_sides[t] & 1;
  }
  EXPECT_GE(front_unlit, 4);  // the box's sides at -x and +z, and its bottom, face away from the light
  RenderParams p;
  p.width = p.height = 48;
  p.max_depth = 8;
  Renderer renderer(2);
  Film a(p.width, p.height), b(p.width, p.height);
  RenderCounters ca, cb;
  for (uint32_t f = 0; f < 4; ++f) {
    renderer.render_frame(rs, p, a, f, ca);
    renderer.render_frame(cleared, p, b, f, cb);
  }
  EXPECT_EQ(a.sum, b.sum);
  EXPECT_EQ(a.half_sum, b.half_sum);
  EXPECT_EQ(ca.shadow_rays, cb.shadow_rays);
  EXPECT_EQ(ca.shadow_skipped_zero_bsdf, cb.shadow_skipped_zero_bsdf);
  EXPECT_EQ(ca.shadow_skipped_backfacing, cb.shadow_skipped_backfacing);
}

}  // namespace
}  // namespace pt
