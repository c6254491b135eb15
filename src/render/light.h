#pragma once
/// Area lights: the emissive shapes of a scene. A light is picked in proportion to its power, then a point on it is
/// sampled; every pdf is returned in solid angle at the receiving point (the area-to-solid-angle conversion lives
/// only in this module, pbrt-v4 section 4.2.3).
#include <cstdint>
#include <span>
#include <vector>

#include "core/ray.h"
#include "core/sampling.h"

namespace pt {

/// How a light point is sampled. solid_angle: spherical rectangles, parallelograms (two spherical triangles) and
/// triangles wherever they are usable; area: uniform by area;
/// automatic (the default): solid angle only where area sampling's density is far enough from it for the better
/// distribution to pay for its cost, else area (kAutoMinSpread below; integrator.cpp VertexLightSampling; per scene at
/// the first vertex, render/auto_light_sampling.h).
enum class LightSampling : int { area = 0, solid_angle = 1, automatic = 2 };

enum class LightKind : uint8_t { rect, triangle, sphere };

/// One emitter. rect: corner p0, edges e1/e2 (parallelogram). triangle: p0, p0+e1, p0+e2. sphere: center p0,
/// radius. `n` is the front normal for planar lights. Emission leaves the front (outward for spheres) only.
struct Light {
  LightKind kind = LightKind::rect;
  vec3 p0{0.0f}, e1{0.0f}, e2{0.0f};
  vec3 n{0.0f, 0.0f, 1.0f};
  float radius = 0.0f;
  float area = 0.0f;
  bool rectangular = false;  ///< rect with orthogonal edges: a spherical rectangle (else two spherical triangles)
  vec2 inv_len2{0.0f};       ///< rectangular: 1 / |e1|^2, 1 / |e2|^2 (for LightSampling::automatic's test)
  RectangleFrame rect_frame;  ///< rectangular: what spherical rectangles need of the light, computed once
  /// Planar lights: |p0| + |e1| + |e2| per axis, the magnitude a sampled point's rounding error scales with
  /// (light.cpp, planar_point_error). Computed once: per sample it was nine absolute values and six additions.
  vec3 point_magnitude{0.0f};
  vec3 emission{0.0f};
};

/// A point sampled on a light, as seen from a receiving point.
struct LightSample {
  SurfacePoint point;   ///< on the light, with its rounding bound, for the shadow ray
  vec3 wi{0.0f};        ///< unit direction from the receiver to the point
  float dist = 0.0f;
  vec3 radiance{0.0f};  ///< emitted radiance toward the receiver (0 from the back side)
  float pdf = 0.0f;     ///< solid-angle density of this light's sampling at the receiver (light choice excluded)
};

Light make_rect_light(vec3 corner, vec3 edge1, vec3 edge2, vec3 emission);
Light make_triangle_light(vec3 p0, vec3 p1, vec3 p2, vec3 emission);
Light make_sphere_light(vec3 center, float radius, vec3 emission);

/// Emitted power (luminance-weighted), the weight for picking a light.
float light_power(const Light& light);

/// Solid-angle sampling pays off only between these bounds; outside them float precision (tiny or grazing
/// rectangles) or the near-hemisphere case make uniform area sampling the better choice (pbrt-v4 uses the same
/// thresholds, MinSphericalSampleArea and MaxSphericalSampleArea, for triangles and bilinear patches). They apply
/// under every LightSampling mode.
inline constexpr float kMinSolidAngle = 3e-4f;
inline constexpr float kMaxSolidAngle = 6.22f;

/// LightSampling::automatic samples a rectangle or triangle by solid angle where area sampling's solid-angle density
/// varies over it by at least this factor (max / min; rect_area_density_spreads in light.cpp,
/// triangle_area_density_spread below), by area elsewhere.
/// The integrator asks for more at deeper path vertices (integrator.cpp, VertexLightSampling).
/// Both thresholds were chosen with bench-error (issue 11). At the first vertex 1.5: on the lit plane it keeps all
/// of solid angle's gain (rel_mse 6.81e-7 at 64 spp, as solid angle everywhere; 2 left 7.60e-7, a ratio the time
/// saved did not make up once roulette stopped hiding direct-light noise, docs/BENCHMARKS.md "Eighth round"). On the
/// Cornell scenes it sends most first vertices to solid angle for no visible gain (rel_mse the same to three digits)
/// at 6-8% of the frame time, so the first vertex takes it only where a per-scene pilot finds that it pays
/// (render/auto_light_sampling.h); elsewhere the first vertex asks for kAutoMinSpreadDeep too.
inline constexpr float kAutoMinSpread = 1.5f;
/// The spread from which deeper path vertices (behind a diffuse bounce) take solid angle: only close to a light.
inline constexpr float kAutoMinSpreadDeep = 8.0f;

/// Samples a point on `light` as seen from `ref`. Returns false when nothing can arrive (back side, degenerate).
bool sample_light(const Light& light, vec3 ref, vec2 u, LightSampling mode, LightSample& out,
                  float auto_min_spread = kAutoMinSpread);

/// The solid-angle pdf with which sample_light would produce the point `p_light` with normal `n_light`,
/// reached from `ref` along unit direction `wi` at distance `dist`. Used for MIS when a BSDF ray hits a light.
float light_pdf(const Light& light, vec3 ref, vec3 wi, float dist, vec3 n_light, LightSampling mode,
                float auto_min_spread = kAutoMinSpread);

/// Whether every point of `light` lies below the plane with unit normal `n` through each of `points` (a triangle's
/// corners: on one plane up to rounding), by a margin far beyond what the rounding of a sampled point and of the
/// receiver's test could make up (kBelowPlaneMargin in light.cpp): then from any point of their convex hull every
/// sample_light direction wi has dot(wi, n) < 0, where the BSDF's geometric test (bsdf.h, eval_bsdf_cos) gives
/// zero. A test on the light's corners (sphere: its center and radius). render_scene.cpp runs it per triangle at
/// scene build (RenderScene::tri_unlit_sides), so the integrator can skip a light sample with the same result: asked
/// per light sample it cost more than the sampling it saved (issue 11).
bool light_below_plane(const Light& light, std::span<const vec3> points, vec3 n);

/// All lights of a scene with the power distribution to choose among them.
struct LightSet {
  std::vector<Light> lights;
  DiscreteDistribution power;

  void finalize();  ///< builds `power` from the lights
  bool empty() const { return lights.empty(); }
};

/// How far uniform area sampling of a triangle light is from the solid-angle density at `ref`: the ratio of its
/// largest to smallest solid-angle density over the triangle, (r_max / r_min)^3 (that density is A h / r^3 for a
/// receiver at height h), with r_min the distance to the triangle's nearest point and r_max to its farthest vertex.
/// The triangle's counterpart of the rectangles' per-receiver area / solid-angle choice.
float triangle_area_density_spread(const Light& light, vec3 ref);

}  // namespace pt
