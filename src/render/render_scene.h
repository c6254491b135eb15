#pragma once
/// What the integrator traces: the scene flattened into triangles and spheres behind one BVH, per-primitive
/// material and light ids, the light set, and feature flags that let the hot loop skip what a scene lacks.
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "accel/geometry.h"
#include "render/light.h"
#include "scene/scene.h"

namespace pt {

/// The surface at a ray hit, in world space.
struct SurfaceHit {
  SurfacePoint sp;       ///< position with error bound and geometric normal (front = CCW / outward)
  vec3 ns{0, 0, 1};      ///< shading normal, on the same side as sp.ng
  uint32_t material = 0;
  int32_t light = -1;    ///< index into lights, or -1
  uint8_t unlit_sides = 0;  ///< RenderScene::tri_unlit_sides of the triangle hit (0 for spheres)
};

/// Scene features the integrator specializes on.
struct SceneFeatures {
  bool has_delta = false;       ///< some material scatters into delta directions only (info_of(type).delta)
  bool has_background = false;
  uint32_t material_types = 0;  ///< bit (1 << int(type)) for every material type present, for the stats
};

/// What make_surface_hit needs of a triangle beyond its vertices, computed once per triangle rather than at every
/// hit (issue 11: the normal's square root and division were the largest cost of a hit). Exactly the values the
/// per-hit computation gave, so images do not change.
struct TriangleShading {
  vec3 ng{0.0f};             ///< unit geometric normal (front = CCW); unused when !valid_ng
  bool valid_ng = false;     ///< false for a degenerate triangle: its hits take -ray.dir as their normal
  bool has_normals = false;  ///< some corner has a shading normal (else the shading normal is ng)
};

/// The immutable, heavy part of a render scene: flattened primitives and the BVH. Shared (not copied) between
/// versions of a scene that differ only in materials, lights' emission, camera or background.
struct RenderGeometry {
  /// Everything below is stored relative to this point (the center of the scene's bounds), so a scene far from
  /// the world origin is traced with small coordinates and small rounding errors ("camera-relative" rendering).
  vec3 origin{0.0f};
  /// ... and scaled by this power of two: 1 for scenes between 2^-20 and 2^20 across, else what brings the scene to
  /// about 1 across. Float squares of lengths (normals, areas, distances) overflow beyond about 1e19 and underflow
  /// below 1e-19, so a scene 1e10 across lost its lights (their area overflowed) and one 1e-13 across its shading;
  /// multiplying by a power of two is exact, and radiance does not depend on scale, so the image is the same.
  float scale = 1.0f;
  // Triangles: meshes first (in order), then two per quad. Vertex triples, per-corner shading normals (zero when
  // the triangle has none), material per triangle.
  std::vector<vec3> tri_vertices;
  std::vector<vec3> tri_normals;
  std::vector<TriangleShading> tri_shading;  ///< per triangle, from tri_vertices and tri_normals
  std::vector<uint32_t> tri_material;
  uint32_t quad_first_triangle = 0;  ///< triangles from here on come in pairs, one pair per scene quad
  std::vector<SphereShape> spheres;
  std::vector<uint32_t> sphere_material;
  TraceGeometry trace;
  size_t degenerate_triangles = 0;

  uint32_t triangle_count() const { return uint32_t(tri_material.size()); }
};

/// Flattens the shapes of `scene` and builds the BVH.
std::shared_ptr<const RenderGeometry> make_render_geometry(const Scene& scene, const BvhBuildOptions& options = {});

struct RenderScene {
  std::shared_ptr<const RenderGeometry> geo;
  std::vector<Material> materials;
  std::vector<int32_t> tri_light;     ///< per triangle: index into lights, or -1
  std::vector<int32_t> sphere_light;  ///< per sphere
  /// Per triangle, the sides that no light can reach (light_below_plane of its corners, for every light): bit 0
  /// the front (ng) side, bit 1 the back side. Direct light there is zero whatever light sample is drawn, so the
  /// integrator skips sampling (issue 11: the Cornell boxes' far sides took 13% of the light samples and the whole
  /// sampling cost before being rejected; a per-hit plane test cost more than it saved). Only computed for scenes
  /// with at most kMaxLightsForUnlitSides lights (it costs triangles x lights), else all zero.
  std::vector<uint8_t> tri_unlit_sides;
  LightSet lights;
  vec3 background{0.0f};
  SceneFeatures features;
  Camera camera;  ///< relative to geo->origin, like the geometry
  /// LightSampling::automatic's spread threshold at a path's first non-delta vertex (light.h), for this scene and
  /// camera: kAutoMinSpread where the pilot of render/auto_light_sampling.h finds that solid-angle sampling there
  /// pays for its time, else kAutoMinSpreadDeep. make_render_scene sets it; so must whatever changes the camera,
  /// lights or materials of a copy (update_auto_light_sampling), or it marks the copy auto_pilot_pending.
  float auto_first_spread = kAutoMinSpread;
  /// auto_first_spread is stale: the pilot is left to RenderSession, which runs it on its driver thread after an
  /// epoch's preview and before its first kept frame, so the viewer's edits do not wait for it on the UI thread
  /// (1.4-3 ms). Renderer and trace_path never run it: give them scenes where this is false.
  bool auto_pilot_pending = false;
  /// The pilot's estimate behind that choice: the share of the image's variance that solid-angle sampling at the
  /// first vertex removes. NaN when nothing was measured (no light whose sampling the choice affects).
  float auto_pilot_gain = std::numeric_limits<float>::quiet_NaN();

  const TraceGeometry& trace() const { return geo->trace; }
  uint32_t triangle_count() const { return geo->triangle_count(); }
};

/// Flattens `scene` and builds the BVH. The scene should be finalized (it has a camera).
RenderScene make_render_scene(const Scene& scene, const BvhBuildOptions& bvh_options = {});

/// When make_render_scene runs the pilot of LightSampling::automatic (render/auto_light_sampling.h): now, or
/// deferred to the RenderSession that renders the scene (RenderScene::auto_pilot_pending; the viewer's edits).
enum class AutoPilot { now, deferred };

/// A render scene over existing geometry with the materials, background and camera of `scene` (whose shapes
/// must be those `geo` was built from): a material or camera edit costs no BVH rebuild.
RenderScene make_render_scene(const Scene& scene, std::shared_ptr<const RenderGeometry> geo,
                              AutoPilot pilot = AutoPilot::now);

/// Geometry with the shapes of `scene` moved (the same triangles and spheres as when `geo` was built: only mesh
/// positions and shading normals, quads, and sphere centres and radii changed), refitted, not rebuilt: what an
/// interactive light edit costs. Equal to a rebuild with geo's origin and scale. A scene with other counts returns an
/// unchanged copy.
std::shared_ptr<const RenderGeometry> refit_render_geometry(const RenderGeometry& geo, const Scene& scene);

/// The scene material of primitive `prim` (triangles first, then spheres), as the BVH reports hits.
inline uint32_t primitive_material(const RenderGeometry& g, uint32_t prim) {
  return prim < g.triangle_count() ? g.tri_material[prim] : g.sphere_material[prim - g.triangle_count()];
}

/// A world-space point in the render frame (origin-shifted and scaled, RenderGeometry::origin and scale).
inline vec3 to_render_point(const RenderGeometry& g, vec3 world) { return (world - g.origin) * g.scale; }

/// A world-space ray in the render scene's frame, for callers outside the camera: tests, picking.
inline Ray to_render_frame(const RenderScene& rs, Ray ray) {
  ray.org = to_render_point(*rs.geo, ray.org);
  ray.tmax *= rs.geo->scale;
  return ray;
}

/// Surface details of a hit: position reconstructed from barycentrics (pbrt-v4 section 6.8.5 error bounds).
SurfaceHit make_surface_hit(const RenderScene& rs, const Ray& ray, const Hit& hit);

}  // namespace pt
