// The render scene (src/render/render_scene.cpp): what the integrator reads at a hit, and the geometry a light edit
// refits instead of rebuilding.
//  - a refit of moved (here: rotated) geometry equals a rebuild of it: vertices, shading normals, per-triangle
//    shading, spheres, and the hits of the refitted tree;
//  - a shading normal given on the far side of its triangle is turned to the geometric normal's side;
//  - every primitive reads its own material, and a world ray keeps its world length in the render frame.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "core/rng.h"
#include "core/sampling.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "render/scene_builders.h"

namespace pt {
namespace {

/// A square pyramid (base [-1, 1]^2 at z = 0, apex at z = 1, faces outward) with smooth per-vertex normals, a small
/// quad and a sphere inside its bounds. Turning it by 90 degrees about z keeps its bounds, so the render frame's
/// origin (the bounds' centre) is the same for the refit and the rebuild.
Scene pyramid_scene() {
  Scene s;
  test::add_material(s, test::diffuse(vec3(0.5f)));
  Mesh m;
  m.positions = {vec3(-1, -1, 0), vec3(1, -1, 0), vec3(1, 1, 0), vec3(-1, 1, 0), vec3(0, 0, 1)};
  m.indices = {uvec3(0, 1, 4), uvec3(1, 2, 4), uvec3(2, 3, 4), uvec3(3, 0, 4), uvec3(0, 3, 2), uvec3(0, 2, 1)};
  for (vec3 p : m.positions) m.normals.push_back(glm::normalize(p - vec3(0, 0, 0.4f)));
  m.normal_indices = m.indices;
  m.materials.assign(m.indices.size(), 0);
  s.meshes.push_back(m);
  s.quads.push_back({vec3(-0.2f, -0.1f, 0.3f), vec3(0.3f, 0, 0), vec3(0, 0.2f, 0), 0});
  s.spheres.push_back({vec3(0.1f, 0.2f, 0.5f), 0.1f, 0});
  return s;
}

/// (x, y, z) -> (-y, x, z), exactly.
vec3 quarter_turn(vec3 p) { return vec3(-p.y, p.x, p.z); }

bool same_bits(vec3 a, vec3 b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// The scene scaled by f, a power of two (exact).
Scene scaled(Scene s, float f) {
  for (vec3& p : s.meshes[0].positions) p *= f;
  for (Quad& q : s.quads) q = {q.corner * f, q.edge1 * f, q.edge2 * f, q.material};
  for (Sphere& sp : s.spheres) {
    sp.center *= f;
    sp.radius *= f;
  }
  return s;
}

/// The scene scales the parametrized tests run at: at 2^-70 and 2^70 the render frame is scaled
/// (RenderGeometry::scale), at 1 it is not.
const auto kScales = testing::Values(1.0f, 0x1p-70f, 0x1p70f);

class RefitAtScale : public testing::TestWithParam<float> {};

// The refit must scale as the build did.
INSTANTIATE_TEST_SUITE_P(RenderGeometry, RefitAtScale, kScales);

TEST_P(RefitAtScale, ARefitOfMovedGeometryEqualsARebuild) {
  Scene before = scaled(pyramid_scene(), GetParam()), after = before;
  for (vec3& p : after.meshes[0].positions) p = quarter_turn(p);
  for (vec3& n : after.meshes[0].normals) n = quarter_turn(n);
  Quad& q = after.quads[0];
  q = {quarter_turn(q.corner), quarter_turn(q.edge1), quarter_turn(q.edge2), q.material};
  after.spheres[0].center = quarter_turn(after.spheres[0].center);
  const auto old_geo = make_render_geometry(before, {});
  const auto refit = refit_render_geometry(*old_geo, after);
  const auto rebuilt = make_render_geometry(after, {});
  ASSERT_TRUE(same_bits(refit->origin, rebuilt->origin));
  ASSERT_EQ(refit->scale, rebuilt->scale);
  EXPECT_EQ(rebuilt->scale == 1.0f, GetParam() == 1.0f);
  ASSERT_EQ(refit->triangle_count(), rebuilt->triangle_count());
  for (size_t i = 0; i < rebuilt->tri_vertices.size(); ++i) {
    EXPECT_TRUE(same_bits(refit->tri_vertices[i], rebuilt->tri_vertices[i])) << "vertex " << i;
    EXPECT_TRUE(same_bits(refit->tri_normals[i], rebuilt->tri_normals[i])) << "normal " << i;
  }
  for (uint32_t t = 0; t < rebuilt->triangle_count(); ++t) {
    const TriangleShading &a = refit->tri_shading[t], &b = rebuilt->tri_shading[t];
    EXPECT_TRUE(same_bits(a.ng, b.ng) && a.valid_ng == b.valid_ng && a.has_normals == b.has_normals) << "triangle " << t;
  }
  ASSERT_EQ(refit->spheres.size(), 1u);
  EXPECT_TRUE(same_bits(refit->spheres[0].center, rebuilt->spheres[0].center));
  // The refitted tree finds what the rebuilt one finds (rays in the render frame, where the pyramid is
  // 2 * GetParam() * scale across).
  Pcg32 rng(3, 4);
  int hits = 0;
  const float frame = GetParam() * rebuilt->scale;
  for (int i = 0; i < 2000; ++i) {
    const vec3 org = 3.0f * frame * sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
    const vec3 to = frame * (vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 2.0f - 1.0f);
    Ray ra{org, glm::normalize(to - org), kInfinity}, rb = ra;
    Hit ha, hb;
    const bool a = intersect_closest(refit->trace, ra, ha), b = intersect_closest(rebuilt->trace, rb, hb);
    ASSERT_EQ(a, b) << "ray " << i;
    if (!a) continue;
    EXPECT_EQ(ha.prim, hb.prim) << "ray " << i;
    EXPECT_EQ(ha.t, hb.t) << "ray " << i;
    ++hits;
  }
  EXPECT_GT(hits, 1000);
}

TEST(RenderScene, EachPrimitiveReadsItsOwnMaterial) {
  // The BVH numbers triangles first (meshes, then two per quad), then spheres: primitive_material must read the
  // first sphere's material, not one past the last triangle's.
  Scene s = pyramid_scene();
  const uint32_t quad_material = test::add_material(s, test::diffuse(vec3(0.2f)));
  const uint32_t sphere_material = test::add_material(s, test::diffuse(vec3(0.9f)));
  s.quads[0].material = quad_material;
  s.spheres[0].material = sphere_material;
  s.spheres.push_back({vec3(-0.1f, -0.2f, 0.5f), 0.05f, quad_material});
  const auto geo = make_render_geometry(s, {});
  const uint32_t n = geo->triangle_count();
  ASSERT_EQ(n, 8u);  // six mesh triangles and the quad's two
  for (uint32_t t = 0; t < 6; ++t) EXPECT_EQ(primitive_material(*geo, t), 0u) << "triangle " << t;
  EXPECT_EQ(primitive_material(*geo, 6), quad_material);
  EXPECT_EQ(primitive_material(*geo, 7), quad_material);
  EXPECT_EQ(primitive_material(*geo, n), sphere_material);
  EXPECT_EQ(primitive_material(*geo, n + 1), quad_material);
}

class RenderFrameAtScale : public testing::TestWithParam<float> {};

INSTANTIATE_TEST_SUITE_P(RenderGeometry, RenderFrameAtScale, kScales);

TEST_P(RenderFrameAtScale, AWorldRayEndsAtItsWorldLength) {
  // to_render_frame moves a world ray into the render frame (shifted and scaled): its origin and its tmax both, so
  // a shadow ray or a pick limited to a world distance stops there whatever the scene's size. A ray from 5 f above
  // the base, straight down, meets the apex (at f) after 4 f.
  const float f = GetParam();
  const RenderScene rs = make_render_scene(scaled(pyramid_scene(), f));
  EXPECT_EQ(rs.geo->scale == 1.0f, f == 1.0f);
  for (const float length : {3.9f, 4.1f}) {
    const Ray ray = to_render_frame(rs, Ray{vec3(0, 0, 5 * f), vec3(0, 0, -1), length * f});
    EXPECT_EQ(intersect_any(rs.trace(), ray), length > 4.0f) << "a ray of " << length << " f";
    Ray closest = ray;
    Hit hit;
    const bool found = intersect_closest(rs.trace(), closest, hit);
    EXPECT_EQ(found, length > 4.0f) << "a ray of " << length << " f";
    if (found) {
      EXPECT_NEAR(hit.t / rs.geo->scale / f, 4.0f, 1e-5f);
    }
  }
}

TEST(RenderScene, AShadingNormalOnTheFarSideIsTurnedToTheGeometricSide) {
  // A floor whose file gives it normals pointing down while its winding faces up (as exporters sometimes write
  // them): the shading normal at a hit from above must be on the geometric normal's side, or the surface would
  // scatter into itself and render black.
  Scene s;
  test::add_material(s, test::diffuse(vec3(0.5f)));
  Mesh m;
  m.positions = {vec3(-1, 0, 1), vec3(1, 0, 1), vec3(1, 0, -1), vec3(-1, 0, -1)};  // counter-clockwise from above
  m.indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
  m.normals = {vec3(0, -1, 0), vec3(0.1f, -1, 0)};
  m.normal_indices = {uvec3(0, 0, 1), uvec3(0, 1, 0)};
  m.materials = {0, 0};
  s.meshes.push_back(m);
  const RenderScene rs = make_render_scene(s);
  for (vec3 org : {vec3(0.3f, 1.0f, 0.2f), vec3(-0.4f, 1.0f, -0.5f)}) {
    Ray ray{org - rs.geo->origin, vec3(0, -1, 0), kInfinity};
    Hit hit;
    ASSERT_TRUE(intersect_closest(rs.trace(), ray, hit));
    const SurfaceHit sh = make_surface_hit(rs, ray, hit);
    EXPECT_GT(sh.sp.ng.y, 0.99f);
    EXPECT_GT(glm::dot(sh.ns, sh.sp.ng), 0.9f) << sh.ns.x << " " << sh.ns.y << " " << sh.ns.z;
  }
}

// Shading normals that are not finite are dropped, as if the mesh had none there: a NaN normal would give every
// bounce from the triangle a NaN direction. Loaders refuse such normals; a scene built in code can still hold them.
TEST(RenderGeometry, NormalsThatAreNotFiniteAreDropped) {
  Scene s = pyramid_scene();
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  s.meshes[0].normals[4] = vec3(inf, 0.0f, 0.0f);  // the apex, a corner of the four sides
  s.meshes[0].normals[0] = vec3(nan, 1.0f, 0.0f);
  s.meshes[0].normals[2] = vec3(-inf, inf, 1.0f);
  const auto geo = make_render_geometry(s, {});
  int dropped = 0;
  for (vec3 n : geo->tri_normals) {
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    dropped += n == vec3(0.0f);
  }
  EXPECT_EQ(dropped, 4 + 4 + 4 + 6) << "the apex in the 4 sides, corners 0 and 2 in 4 triangles each, and the "
                                       "quad's 6 corners (which have no normals)";
  // A triangle keeps shading normals while some corner has one (every pyramid triangle has a finite corner left);
  // the quad's triangles have none.
  for (uint32_t t = 0; t < geo->triangle_count(); ++t) {
    EXPECT_TRUE(geo->tri_shading[t].valid_ng) << "triangle " << t;
    EXPECT_EQ(geo->tri_shading[t].has_normals, t < geo->quad_first_triangle) << "triangle " << t;
  }
}

// OBJ and glTF files may give normals of any length (a vn line is not required to be unit); the renderer interpolates
// the corners' normals, so each must be made unit first, or a long one would pull the interpolated direction toward
// itself. Scaled by a different factor at each corner, the normals give the unit ones of the pyramid.
TEST(RenderGeometry, ShadingNormalsAreUnitWhateverLengthTheSceneGivesThem) {
  Scene s = pyramid_scene();
  const auto unit = make_render_geometry(s, {});
  const float factors[] = {3.0f, 0.25f, 7.0f, 1e-3f, 100.0f};
  for (size_t i = 0; i < s.meshes[0].normals.size(); ++i) s.meshes[0].normals[i] *= factors[i];
  const auto geo = make_render_geometry(s, {});
  ASSERT_EQ(geo->tri_normals.size(), unit->tri_normals.size());
  for (size_t i = 0; i < 3 * size_t(geo->quad_first_triangle); ++i) {
    EXPECT_NEAR(glm::length(geo->tri_normals[i]), 1.0f, 1e-6f) << "corner " << i;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(geo->tri_normals[i][k], unit->tri_normals[i][k], 1e-6f) << "corner " << i;
  }
}

// An emissive triangle with no area has no power: it is not put in the light list, where light sampling would never
// choose it, and a scene whose emitters all lack area has no light to sample (no shadow rays at all). Its emission
// would still count where a BSDF-sampled path hit it, which a zero-area triangle never is.
TEST(RenderScene, AnEmitterWithNoAreaIsNotALight) {
  for (bool with_ceiling_light : {true, false}) {
    Scene s = test::make_test_cornell();
    const uint32_t light = s.quads.back().material;
    if (!with_ceiling_light) s.quads.back().material = 0;
    Mesh m;
    m.positions = {vec3(-0.5f, 1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), vec3(0.5f, 1.0f, 0.0f)};  // on one line
    m.indices = {uvec3(0, 1, 2)};
    m.materials = {light};
    s.meshes.push_back(m);
    const RenderScene rs = make_render_scene(s);
    EXPECT_EQ(rs.lights.lights.size(), with_ceiling_light ? 1u : 0u);
    EXPECT_EQ(rs.tri_light[0], -1) << "the mesh's triangle comes first";
    RenderParams p;
    p.width = p.height = 16;
    p.max_depth = 4;
    Renderer renderer(2);
    Film film(p.width, p.height);
    RenderCounters c;
    renderer.render_frame(rs, p, film, 0, c);
    EXPECT_EQ(c.nonfinite_samples, 0u);
  }
}

// A refit keeps the build's render frame scale, so geometry moved far beyond the built bounds can reach coordinates
// whose edge cross product overflows float; its geometric normal then comes from double (render_scene.cpp,
// triangle_shading) and is the rebuilt scene's direction, not none.
TEST(RenderGeometry, ARefitFarBeyondTheBuildsBoundsKeepsTheGeometricNormals) {
  const Scene before = pyramid_scene(), after = scaled(before, 0x1p66f);
  const auto geo = make_render_geometry(before, {});
  ASSERT_EQ(geo->scale, 1.0f);
  const auto refit = refit_render_geometry(*geo, after);
  const auto rebuilt = make_render_geometry(after, {});
  for (uint32_t t = 0; t < refit->triangle_count(); ++t) {
    const vec3* v = &refit->tri_vertices[3 * t];
    ASSERT_FALSE(std::isfinite(glm::length(glm::cross(v[1] - v[0], v[2] - v[0])))) << "triangle " << t;
    const TriangleShading &a = refit->tri_shading[t], &b = rebuilt->tri_shading[t];
    ASSERT_TRUE(a.valid_ng) << "triangle " << t;
    EXPECT_NEAR(glm::length(a.ng), 1.0f, 1e-6f);
    EXPECT_GT(glm::dot(a.ng, b.ng), 0.99999f) << "triangle " << t;
  }
}

// The scene's feature flags (which kernel the integrator compiles in, and the stats JSON's features) cover every
// material, wherever it stands in the list.
TEST(RenderScene, FeatureFlagsCoverEveryMaterialWhereverItStands) {
  Material glass;
  glass.type = MaterialType::glass;
  glass.ior = 1.5f;
  struct Case {
    std::vector<Material> materials;
    bool delta;
  };
  const Case cases[] = {{{test::diffuse(vec3(0.5f))}, false},
                        {{test::mirror(vec3(0.9f)), test::diffuse(vec3(0.5f))}, true},
                        {{test::diffuse(vec3(0.5f)), glass, test::diffuse(vec3(0.2f))}, true},
                        {{test::diffuse(vec3(0.5f)), test::mirror(vec3(0.9f))}, true}};
  for (const Case& c : cases) {
    Scene s = pyramid_scene();
    s.materials = c.materials;
    const RenderScene rs = make_render_scene(s);
    EXPECT_EQ(rs.features.has_delta, c.delta) << c.materials.size() << " materials";
    uint32_t types = 0;
    for (const Material& m : c.materials) types |= 1u << unsigned(m.type);
    EXPECT_EQ(rs.features.material_types, types) << c.materials.size() << " materials";
  }
}

}  // namespace
}  // namespace pt
