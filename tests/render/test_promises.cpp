// README promises checked against computed answers: the camera model, emission from the front only with
// scattering on both sides, lights picked in proportion to power, --max-depth as a truncated geometric series, and
// the specialised path kernels against the generic one.
//
// Statistical checks compare a mean of n independent samples with its closed form within 5 standard errors (plus a
// tiny absolute slack for float rounding): a two-sided normal false-alarm rate of 5.7e-7 per check, under 1e-4 for
// this whole file. Every other check is deterministic.
#include <gtest/gtest.h>

#include <cmath>

#include "render/analytic.h"
#include "render/camera.h"
#include "render/names.h"
#include "render/renderer.h"
#include "scene_builders.h"

namespace pt {
namespace {

using test::add_material;
using test::diffuse;

const IntegratorKind kIntegrators[] = {IntegratorKind::mis, IntegratorKind::nee, IntegratorKind::bsdf};

struct Estimate {
  double mean = 0.0;
  double stderr_ = 0.0;
};

/// Mean and standard error of channel x of the radiance along the world-space ray, over n independent samples.
Estimate estimate(const RenderScene& rs, const RenderParams& params, const Ray& ray_world, int n, uint64_t seed) {
  const Ray ray = to_render_frame(rs, ray_world);
  RenderCounters counters;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    PixelSampler sampler = PixelSampler::start(seed, 777, uint64_t(i), SamplerKind::independent);
    vec3 L = trace_path(rs, params, ray, sampler, counters);
    sum += L.x;
    sum2 += double(L.x) * L.x;
  }
  Estimate e;
  e.mean = sum / n;
  e.stderr_ = std::sqrt(std::max(0.0, sum2 / n - e.mean * e.mean) / n);
  return e;
}

Film render(const RenderScene& rs, RenderParams p, int frames = 1) {
  Renderer renderer(2);
  Film film(p.width, p.height);
  RenderCounters c;
  for (int f = 0; f < frames; ++f) renderer.render_frame(rs, p, film, uint32_t(f), c);
  return film;
}

// ---------------------------------------------------------------------------------------------------------------
// Camera model (README "Camera model"), computed independently in double.

dvec3 readme_direction(const Camera& cam, int W, int H, int i, int j, double u, double v) {
  dvec3 eye(cam.eye), target(cam.target), up(cam.up);
  dvec3 forward = glm::normalize(target - eye);
  dvec3 right = glm::normalize(glm::cross(forward, up));
  dvec3 up2 = glm::cross(right, forward);
  double t = std::tan(double(cam.fov_deg) * M_PI / 360.0);
  double x = (2.0 * (i + u) / W - 1.0) * t * W / H;
  double y = (1.0 - 2.0 * (j + v) / H) * t;
  return glm::normalize(forward + x * right + y * up2);
}

TEST(CameraModel, GenerateCameraRayIsTheReadmeFormula) {
  const Camera cams[] = {
      Camera{vec3(1, 2, 3), vec3(-0.5f, 0.3f, -2), vec3(0.1f, 1, 0.2f), 55.0f},
      Camera{vec3(0, 0, 5), vec3(0, 0, 0), vec3(0, 1, 0), 30.0f},
      Camera{vec3(-4, 1, 0), vec3(2, 0.5f, 1), vec3(0, 0, 1), 100.0f},  // z up
  };
  const int W = 37, H = 23;  // not square: a swapped aspect ratio shows
  for (const Camera& cam : cams) {
    CameraRig rig = make_camera_rig(cam, W, H);
    for (int i : {0, 5, 18, 36})
      for (int j : {0, 11, 22})
        for (vec2 u : {vec2(0.0f), vec2(0.5f), vec2(0.99f, 0.25f)}) {
          Ray r = generate_camera_ray(rig, i, j, u);
          dvec3 want = readme_direction(cam, W, H, i, j, u.x, u.y);
          EXPECT_NEAR(r.dir.x, want.x, 2e-6) << i << "," << j;
          EXPECT_NEAR(r.dir.y, want.y, 2e-6) << i << "," << j;
          EXPECT_NEAR(r.dir.z, want.z, 2e-6) << i << "," << j;
          EXPECT_EQ(r.org, cam.eye);
        }
  }
}

/// Black scene with one emissive square (radiance 1) in the upper left of the view of a camera on +z looking down
/// -z with +y up: only the top-left quadrant of the image may be lit.
Scene upper_left_light_scene() {
  Scene s;
  uint32_t e = add_material(s, diffuse(vec3(0.0f), vec3(1.0f)));
  // Facing +z (toward the camera): cross(e1, e2) = +z.
  s.quads.push_back({vec3(-0.9f, 0.1f, 0.0f), vec3(0.8f, 0, 0), vec3(0, 0.8f, 0), e});
  s.camera = Camera{vec3(0, 0, 3), vec3(0, 0, 0), vec3(0, 1, 0), 40.0f};
  return s;
}

TEST(CameraModel, AnAsymmetricSceneIsNotMirrored) {
  RenderScene rs = make_render_scene(upper_left_light_scene());
  RenderParams p;
  p.width = 24;  // not square
  p.height = 16;
  p.spp_per_frame = 4;
  Image img = render(rs, p).resolve();
  double quadrant[2][2] = {};
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) quadrant[y >= p.height / 2][x >= p.width / 2] += img.at(x, y).x;
  EXPECT_GT(quadrant[0][0], 10.0);      // top left: the light
  EXPECT_EQ(quadrant[0][1], 0.0);       // top right
  EXPECT_EQ(quadrant[1][0], 0.0);       // bottom left
  EXPECT_EQ(quadrant[1][1], 0.0);       // bottom right
}

// ---------------------------------------------------------------------------------------------------------------
// Emission leaves the front side only; every surface scatters on both sides.

TEST(Sidedness, TheBackOfAnEmitterIsBlack) {
  Scene s;
  // Black emitters (albedo 0): whatever reaches a point from elsewhere, only its own emission can leave it.
  uint32_t e = add_material(s, diffuse(vec3(0.0f), vec3(3.0f)));
  s.quads.push_back({vec3(-1, -1, 0), vec3(2, 0, 0), vec3(0, 2, 0), e});  // front +z
  Mesh tri;  // clockwise seen from +z: front -z
  tri.positions = {vec3(-1, -1, -2), vec3(0, 1, -2), vec3(1, -1, -2)};
  tri.indices = {uvec3(0, 1, 2)};
  tri.materials = {e};
  s.meshes.push_back(tri);
  s.spheres.push_back({vec3(0, 0, -6), 1.0f, e});  // outward
  RenderScene rs = make_render_scene(s);
  for (IntegratorKind k : kIntegrators) {
    RenderParams p;
    p.integrator = k;
    p.max_depth = 5;
    RenderCounters c;
    for (int i = 0; i < 64; ++i) {
      PixelSampler sampler = PixelSampler::start(1, 2, uint64_t(i));
      // Seen from the front: exactly the emission at max depth 0.
      RenderParams p0 = p;
      p0.max_depth = 0;
      Ray front{vec3(0.1f, 0.2f, 1.0f), vec3(0, 0, -1), kInfinity};
      EXPECT_EQ(trace_path(rs, p0, to_render_frame(rs, front), sampler, c), vec3(3.0f));
      // Between the quad and the triangle, both show their backs.
      Ray back_of_quad{vec3(0.1f, 0.2f, -1.0f), vec3(0, 0, 1), kInfinity};
      EXPECT_EQ(trace_path(rs, p, to_render_frame(rs, back_of_quad), sampler, c), vec3(0.0f))
          << name_of(k);
      Ray back_of_triangle{vec3(0.1f, -0.2f, -1.0f), vec3(0, 0, -1), kInfinity};
      EXPECT_EQ(trace_path(rs, p, to_render_frame(rs, back_of_triangle), sampler, c), vec3(0.0f))
          << name_of(k);
      Ray front_of_triangle{vec3(0.1f, -0.2f, -3.0f), vec3(0, 0, 1), kInfinity};
      EXPECT_EQ(trace_path(rs, p0, to_render_frame(rs, front_of_triangle), sampler, c), vec3(3.0f));
      // Inside the sphere: its inner side is its back.
      Ray inside_sphere{vec3(0.1f, 0.2f, -6.0f), glm::normalize(vec3(0.3f, -0.2f, 1.0f)), kInfinity};
      EXPECT_EQ(trace_path(rs, p, to_render_frame(rs, inside_sphere), sampler, c), vec3(0.0f))
          << name_of(k);
    }
  }
}

TEST(Sidedness, AOneSidedQuadLitFromBehindIsLit) {
  // A floor quad whose front faces DOWN (-y), lit by a rectangle light above it and seen from above: the side we
  // see is its back, and it must scatter exactly like a front: albedo / pi * polygon irradiance.
  Scene s;
  const float albedo = 0.5f, radiance = 4.0f;
  add_material(s, diffuse(vec3(albedo)));
  uint32_t emitter = add_material(s, diffuse(vec3(0.0f), vec3(radiance)));
  s.quads.push_back({vec3(-50, 0, -50), vec3(100, 0, 0), vec3(0, 0, 100), 0});  // cross = -y: front faces down
  vec3 c(-0.3f, 1.0f, -0.2f), e1(0.8f, 0, 0), e2(0, 0, 0.5f);                  // light faces down
  s.quads.push_back({c, e1, e2, emitter});
  std::vector<dvec3> poly = {dvec3(c), dvec3(c + e1), dvec3(c + e1 + e2), dvec3(c + e2)};
  RenderScene rs = make_render_scene(s);
  const vec3 x(0.3f, 0.0f, 0.4f);
  const double expected = albedo / M_PI * polygon_irradiance(poly, dvec3(x), dvec3(0, 1, 0), radiance);
  ASSERT_GT(expected, 0.1);
  for (IntegratorKind k : kIntegrators) {
    RenderParams p;
    p.integrator = k;
    p.max_depth = 1;
    Ray ray{x + vec3(0, 0.5f, 0), vec3(0, -1, 0), kInfinity};
    Estimate e = estimate(rs, p, ray, 40000, 3);
    EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-4) << name_of(k);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Lights are picked in proportion to their power; the estimate stays unbiased with several lights.

/// Direct light only (max depth 1) seen straight down at the floor point x (normal +y), for every integrator and
/// light-sampling mode, within 5 standard errors of `expected`.
void expect_direct_light_near(const RenderScene& rs, vec3 x, double expected, int samples, uint64_t seed) {
  for (IntegratorKind k : kIntegrators)
    for (LightSampling mode : {LightSampling::area, LightSampling::solid_angle, LightSampling::automatic}) {
      RenderParams p;
      p.integrator = k;
      p.light_sampling = mode;
      p.max_depth = 1;
      const Ray ray{x + vec3(0, 0.3f, 0), vec3(0, -1, 0), kInfinity};
      const Estimate e = estimate(rs, p, ray, samples, seed);
      EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-4)
          << name_of(k) << " mode " << name_of(mode) << " at " << x.x << "," << x.z;
    }
}

TEST(LightChoice, TwoLightsPickedByPowerAndTheirIrradiancesAdd) {
  Scene s;
  const float albedo = 0.5f;
  add_material(s, diffuse(vec3(albedo)));
  uint32_t dim = add_material(s, diffuse(vec3(0.0f), vec3(1.0f)));
  uint32_t bright = add_material(s, diffuse(vec3(0.0f), vec3(8.0f)));
  s.quads.push_back({vec3(-50, 0, 50), vec3(100, 0, 0), vec3(0, 0, -100), 0});  // floor facing up
  // Both face down; different areas so power is not just radiance: 1 * 0.6 and 8 * 0.1.
  vec3 c1(-1.2f, 1.0f, -0.3f), a1(1.0f, 0, 0), b1(0, 0, 0.6f);
  vec3 c2(0.4f, 0.7f, -0.2f), a2(0.5f, 0, 0), b2(0, 0, 0.2f);
  s.quads.push_back({c1, a1, b1, dim});
  s.quads.push_back({c2, a2, b2, bright});
  RenderScene rs = make_render_scene(s);
  ASSERT_EQ(rs.lights.lights.size(), 2u);
  // The choice: probability in proportion to radiance * area.
  const double power_dim = 1.0 * 0.6, power_bright = 8.0 * 0.1;
  for (size_t i = 0; i < 2; ++i) {
    double want = (rs.lights.lights[i].emission.x == 1.0f ? power_dim : power_bright) / (power_dim + power_bright);
    EXPECT_NEAR(rs.lights.power.pmf(i), want, 1e-6) << i;
  }
  std::vector<dvec3> poly1 = {dvec3(c1), dvec3(c1 + a1), dvec3(c1 + a1 + b1), dvec3(c1 + b1)};
  std::vector<dvec3> poly2 = {dvec3(c2), dvec3(c2 + a2), dvec3(c2 + a2 + b2), dvec3(c2 + b2)};
  for (vec3 x : {vec3(0.0f, 0, 0.0f), vec3(0.6f, 0, -0.1f), vec3(-0.8f, 0, 0.5f)}) {
    double expected = albedo / M_PI *
                      (polygon_irradiance(poly1, dvec3(x), dvec3(0, 1, 0), 1.0) +
                       polygon_irradiance(poly2, dvec3(x), dvec3(0, 1, 0), 8.0));
    expect_direct_light_near(rs, x, expected, 40000, 17);
  }
}

// Every light kind in one scene (rectangle, sheared parallelogram, triangle, sphere), with different radiances and
// areas: the power-based choice among kinds, each kind's density, and MIS between a kind's light sample and a BSDF
// ray that hits another kind must add up to the sum of the closed forms. The planar lights lie in one plane
// (y = 1) and the sphere outside the hull of the lights and the receivers, so nothing shadows anything.
TEST(LightChoice, EveryLightKindInOneSceneAddsUp) {
  Scene s;
  const float albedo = 0.5f;
  add_material(s, diffuse(vec3(albedo)));
  const float l_rect = 1.0f, l_para = 4.0f, l_tri = 6.0f, l_sphere = 3.0f;
  const uint32_t rect = add_material(s, diffuse(vec3(0.0f), vec3(l_rect)));
  const uint32_t para = add_material(s, diffuse(vec3(0.0f), vec3(l_para)));
  const uint32_t tri = add_material(s, diffuse(vec3(0.0f), vec3(l_tri)));
  const uint32_t sphere = add_material(s, diffuse(vec3(0.0f), vec3(l_sphere)));
  s.quads.push_back({vec3(-50, 0, 50), vec3(100, 0, 0), vec3(0, 0, -100), 0});  // floor facing up
  // Facing down: cross(edge1, edge2) = -y for both quads and for the triangle's winding.
  const vec3 rc(-1.2f, 1.0f, -0.3f), ra(1.0f, 0, 0), rb(0, 0, 0.6f);
  const vec3 pc(0.3f, 1.0f, -0.6f), pa(0.6f, 0, 0), pb(0.3f, 0, 0.5f);
  s.quads.push_back({rc, ra, rb, rect});
  s.quads.push_back({pc, pa, pb, para});
  const vec3 t0(-0.6f, 1.0f, 0.5f), t1(0.2f, 1.0f, 0.9f), t2(-0.4f, 1.0f, 1.0f);
  Mesh mesh;
  mesh.positions = {t0, t1, t2};
  mesh.indices = {uvec3(0, 1, 2)};
  mesh.materials = {tri};
  s.meshes.push_back(mesh);
  const vec3 center(1.6f, 0.7f, 1.4f);
  const float radius = 0.2f;
  s.spheres.push_back({center, radius, sphere});
  RenderScene rs = make_render_scene(s);
  ASSERT_EQ(rs.lights.lights.size(), 4u);
  int rectangles = 0, parallelograms = 0, triangles = 0, spheres = 0;
  for (const Light& l : rs.lights.lights) {
    if (l.kind == LightKind::rect) ++(l.rectangular ? rectangles : parallelograms);
    if (l.kind == LightKind::triangle) ++triangles;
    if (l.kind == LightKind::sphere) ++spheres;
  }
  EXPECT_EQ(rectangles, 1);
  EXPECT_EQ(parallelograms, 1);
  EXPECT_EQ(triangles, 1);
  EXPECT_EQ(spheres, 1);

  const std::vector<std::pair<std::vector<dvec3>, double>> polygons = {
      {{dvec3(rc), dvec3(rc + ra), dvec3(rc + ra + rb), dvec3(rc + rb)}, l_rect},
      {{dvec3(pc), dvec3(pc + pa), dvec3(pc + pa + pb), dvec3(pc + pb)}, l_para},
      {{dvec3(t0), dvec3(t1), dvec3(t2)}, l_tri}};
  for (vec3 x : {vec3(0.0f, 0, 0.0f), vec3(0.6f, 0, -0.2f), vec3(-0.7f, 0, 0.4f)}) {
    double irradiance = 0.0;
    for (const auto& [polygon, radiance] : polygons)
      irradiance += polygon_irradiance(polygon, dvec3(x), dvec3(0, 1, 0), radiance);
    irradiance += sphere_irradiance(dvec3(center), radius, dvec3(x), dvec3(0, 1, 0), l_sphere);  // above the horizon
    const double expected = albedo / M_PI * irradiance;
    expect_direct_light_near(rs, x, expected, 200000, 23);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// --max-depth k: in a closed room whose walls emit Le and reflect a, a path of at most k bounces sees
// Le * (1 + a + ... + a^k), for every integrator.

TEST(MaxDepth, ClosedRoomIsATruncatedGeometricSeries) {
  const float a = 0.6f, le = 0.4f;
  Scene s;
  add_material(s, diffuse(vec3(a), vec3(le)));
  test::add_box(s, vec3(-1.0f), vec3(1.0f), 0, true);
  RenderScene rs = make_render_scene(s);
  for (int k : {1, 2, 3, 5}) {
    double expected = 0.0;
    for (int i = 0; i <= k; ++i) expected += le * std::pow(double(a), i);
    for (IntegratorKind kind : kIntegrators)
      for (LightSampling mode : {LightSampling::area, LightSampling::solid_angle, LightSampling::automatic}) {
        RenderParams p;
        p.integrator = kind;
        p.light_sampling = mode;
        p.max_depth = k;
        Ray ray{vec3(0.1f, 0.2f, 0.3f), glm::normalize(vec3(0.3f, -0.5f, 0.8f)), kInfinity};
        Estimate e = estimate(rs, p, ray, 20000, uint64_t(40 + k));
        EXPECT_NEAR(e.mean, expected, 5.0 * e.stderr_ + 1e-5)
            << "max depth " << k << " " << name_of(kind) << " mode " << name_of(mode);
      }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// The path loop is specialised on scene features (no delta materials, no background); the generic loop must give
// the same image bit for bit: both draw the same random numbers and add the same terms (adding a black background
// adds +0).

TEST(Kernels, SpecialisedKernelsEqualTheGenericKernel) {
  for (bool delta : {false, true})
    for (bool background : {false, true}) {
      Scene s = test::make_test_cornell();
      if (!delta) test::make_diffuse_only(s, vec3(0.6f, 0.5f, 0.4f));
      if (background) {
        s.background = vec3(0.3f, 0.4f, 0.5f);
        s.quads.erase(s.quads.begin() + 5);  // open the ceiling so the background is seen
      }
      RenderScene rs = make_render_scene(s);
      ASSERT_EQ(rs.features.has_delta, delta);
      ASSERT_EQ(rs.features.has_background, background);
      for (IntegratorKind k : kIntegrators) {
        RenderParams p;
        p.width = 20;
        p.height = 16;
        p.spp_per_frame = 4;
        p.max_depth = 8;
        p.integrator = k;
        p.sampler = SamplerKind::sobol;
        // The stats JSON's "kernel" names the loop that ran.
        const char* expected = delta ? (background ? "all-materials+background" : "all-materials")
                                     : (background ? "diffuse-only+background" : "diffuse-only");
        EXPECT_STREQ(kernel_name(rs, p), expected);
        Film special = render(rs, p);
        p.force_generic_kernel = true;
        ASSERT_STREQ(kernel_name(rs, p), "generic");
        Film generic = render(rs, p);
        EXPECT_EQ(special.sum, generic.sum) << "delta " << delta << " background " << background << " "
                                            << name_of(k);
        EXPECT_EQ(special.count, generic.count);
        double total = 0;
        for (double v : special.sum) total += v;
        EXPECT_GT(total, 0.0);
      }
    }
}

}  // namespace
}  // namespace pt
