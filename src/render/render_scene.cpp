#include "render/render_scene.h"

#include "render/auto_light_sampling.h"
#include "render/emissive_pairs.h"

namespace pt {

namespace {

/// The unit normal of triangle v (CCW front) and whether its corners' normals n give it shading normals.
TriangleShading triangle_shading(const vec3* v, const vec3* n) {
  TriangleShading ts;
  vec3 ng = glm::cross(v[1] - v[0], v[2] - v[0]);
  float len = glm::length(ng);
  if (!std::isfinite(len)) {
    // The edges or their cross product overflow float (coordinates beyond ~1e19): a NaN normal gave the bounce
    // ray a NaN direction (found by fuzz_render). Double has the range.
    dvec3 c = glm::cross(dvec3(v[1]) - dvec3(v[0]), dvec3(v[2]) - dvec3(v[0]));
    double dl = glm::length(c);
    ng = dl > 0.0 && std::isfinite(dl) ? vec3(c / dl) : vec3(0.0f);
    len = dl > 0.0 && std::isfinite(dl) ? 1.0f : 0.0f;
  }
  ts.valid_ng = len > 0.0f;
  if (ts.valid_ng) ts.ng = ng / len;
  ts.has_normals = n[0] != vec3(0.0f) || n[1] != vec3(0.0f) || n[2] != vec3(0.0f);
  return ts;
}

/// The three corners of every triangle of `mesh` in the render frame (origin o) to v, and their unit shading normals
/// (zero where the mesh has none, or a normal is zero or not finite) to n. Mesh positions are relative to the mesh's
/// origin (double): one rounding into the render frame, the same for every triangle sharing a vertex, so shared
/// edges stay bit-identical (watertight) far from the world origin. The build and the refit both write corners
/// here, so a refit of moved geometry (positions and normals) equals a rebuild.
void write_mesh_corners(const Mesh& mesh, vec3 o, vec3* v, vec3* n) {
  const bool has_normals = !mesh.normal_indices.empty() && mesh.normal_indices.size() == mesh.indices.size();
  const dvec3 shift = mesh.origin - dvec3(o);
  for (size_t t = 0; t < mesh.indices.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      *v++ = vec3(dvec3(mesh.positions[mesh.indices[t][k]]) + shift);
      vec3 normal(0.0f);
      if (has_normals) {
        normal = mesh.normals[mesh.normal_indices[t][k]];
        const float len = glm::length(normal);
        normal = (len > 0.0f && std::isfinite(len)) ? normal / len : vec3(0.0f);
      }
      *n++ = normal;
    }
}

/// RenderGeometry::scale for a scene with these (world) bounds: 1 from 2^-20 to 2^20 across (the images of ordinary
/// scenes stay bit for bit as they were), else 2^-e for the scene's largest extent 2^e <= x < 2^(e+1).
float render_scale(const AABB& bounds) {
  const float across = bounds.empty() ? 0.0f : max_component(bounds.extent());
  if (!(across > 0.0f) || !std::isfinite(across) || (across >= 0x1p-20f && across <= 0x1p20f)) return 1.0f;
  return std::ldexp(1.0f, -std::ilogb(across));
}

/// Multiplies the positions of g (relative to its origin) and the spheres' radii by g.scale: exact, a power of two.
void apply_scale(RenderGeometry& g) {
  if (g.scale == 1.0f) return;
  for (vec3& v : g.tri_vertices) v *= g.scale;
  for (SphereShape& s : g.spheres) {
    s.center *= g.scale;
    s.radius *= g.scale;
  }
}

/// Fills g.tri_shading from g.tri_vertices and g.tri_normals.
void compute_triangle_shading(RenderGeometry& g) {
  g.tri_shading.resize(g.triangle_count());
  for (uint32_t t = 0; t < g.triangle_count(); ++t)
    g.tri_shading[t] = triangle_shading(&g.tri_vertices[3 * t], &g.tri_normals[3 * t]);
}

/// find_unlit_sides's bound on the light count. Its work is triangles x lights, redone on every material edit: about
/// 40 ns a triangle with one light (4 ms on the 100k-triangle cornell-large-mesh, a tenth of its BVH build), and with
/// many lights every one of them must lie below a side for it to count, which gets rare.
constexpr size_t kMaxLightsForUnlitSides = 4;

/// Fills rs.tri_unlit_sides (render_scene.h). A point hit on a triangle is a convex combination of its corners up to
/// rounding far below light_below_plane's margin, so a light below the triangle's plane is below it at every hit, on
/// the side whose normal eval_bsdf_cos tests (sc.ng: +-ng, exactly).
void find_unlit_sides(RenderScene& rs) {
  const RenderGeometry& g = *rs.geo;
  rs.tri_unlit_sides.assign(g.triangle_count(), 0);
  if (rs.lights.empty() || rs.lights.lights.size() > kMaxLightsForUnlitSides) return;
  auto unlit = [&](const vec3* v, vec3 n) {
    for (const Light& l : rs.lights.lights)
      if (!light_below_plane(l, std::span<const vec3>(v, 3), n)) return false;
    return true;
  };
  for (uint32_t t = 0; t < g.triangle_count(); ++t) {
    const TriangleShading& ts = g.tri_shading[t];
    if (!ts.valid_ng) continue;  // its hits take the ray's direction as normal
    const vec3* v = &g.tri_vertices[3 * t];
    rs.tri_unlit_sides[t] = uint8_t((unlit(v, ts.ng) ? 1 : 0) | (unlit(v, -ts.ng) ? 2 : 0));
  }
}

/// Recomputes everything that depends on materials: which primitives are lights, the light set, feature flags.
void rebuild_lights(RenderScene& rs) {
  const RenderGeometry& g = *rs.geo;
  rs.lights.lights.clear();
  rs.tri_light.assign(g.triangle_count(), -1);
  rs.sphere_light.assign(g.spheres.size(), -1);
  rs.features = {};
  rs.features.has_background = !is_black(rs.background);
  for (const Material& m : rs.materials) {
    rs.features.has_delta |= info_of(m.type).delta;
    rs.features.material_types |= 1u << unsigned(m.type);
  }
  auto add = [&](const Light& l) -> int32_t {
    if (!(light_power(l) > 0.0f)) return -1;  // never sampled; BSDF hits still see its emission
    rs.lights.lights.push_back(l);
    return int32_t(rs.lights.lights.size() - 1);
  };
  const uint32_t tri_count = g.triangle_count();
  // Mesh triangles pair into parallelogram lights (render/emissive_pairs.h); a pair's light takes the place of its
  // first triangle in the light list.
  std::vector<uint8_t> emissive(g.quad_first_triangle);
  for (uint32_t t = 0; t < g.quad_first_triangle; ++t) emissive[t] = rs.materials[g.tri_material[t]].emissive();
  const std::vector<int32_t> partner = pair_parallelograms(
      std::span<const vec3>(g.tri_vertices).first(3 * size_t(g.quad_first_triangle)), g.tri_material, emissive);
  for (uint32_t t = 0; t < tri_count; ++t) {
    const Material& m = rs.materials[g.tri_material[t]];
    if (!m.emissive()) continue;
    const vec3* v = &g.tri_vertices[3 * t];
    if (t >= g.quad_first_triangle) {
      // A quad's two triangles share one rectangle light; the first triangle's edges are the quad's edges.
      if ((t - g.quad_first_triangle) % 2 == 1) continue;
      int32_t id = add(make_rect_light(v[0], v[1] - v[0], v[2] - v[0], m.emission));
      rs.tri_light[t] = rs.tri_light[t + 1] = id;
      continue;
    }
    const int32_t u = partner[t];
    if (u < 0) {
      rs.tri_light[t] = add(make_triangle_light(v[0], v[1], v[2], m.emission));
    } else if (uint32_t(u) > t) {
      vec3 corner, e1, e2;
      parallelogram_of(v, &g.tri_vertices[3 * size_t(u)], corner, e1, e2);  // true: the pair was made by it
      rs.tri_light[t] = rs.tri_light[u] = add(make_rect_light(corner, e1, e2, m.emission));
    }
  }
  for (size_t s = 0; s < g.spheres.size(); ++s) {
    const Material& m = rs.materials[g.sphere_material[s]];
    if (m.emissive()) rs.sphere_light[s] = add(make_sphere_light(g.spheres[s].center, g.spheres[s].radius, m.emission));
  }
  rs.lights.finalize();
  find_unlit_sides(rs);
}

}  // namespace

std::shared_ptr<const RenderGeometry> make_render_geometry(const Scene& scene, const BvhBuildOptions& options) {
  auto geo = std::make_shared<RenderGeometry>();
  RenderGeometry& g = *geo;
  const uint32_t material_count = uint32_t(std::max<size_t>(1, scene.materials.size()));
  auto clamp_material = [&](uint32_t m) { return m < material_count ? m : 0u; };
  AABB bounds;
  for (const Mesh& mesh : scene.meshes)
    for (uint32_t i = 0; i < mesh.positions.size(); ++i)
      if (vec3 p = mesh.world_position(i); is_finite(p)) bounds.extend(p);
  for (const Quad& q : scene.quads) {
    bounds.extend(q.corner);
    bounds.extend(q.corner + q.edge1 + q.edge2);
  }
  for (const Sphere& s : scene.spheres) bounds.extend(s.center);
  g.origin = bounds.empty() || !is_finite(bounds.center()) ? vec3(0.0f) : bounds.center();
  const vec3 o = g.origin;
  size_t tri_total = scene.triangle_count();
  g.tri_vertices.reserve(3 * tri_total);
  g.tri_normals.reserve(3 * tri_total);
  g.tri_material.reserve(tri_total);
  for (const Mesh& mesh : scene.meshes) {
    const size_t at = g.tri_vertices.size();  // tri_normals has as many
    g.tri_vertices.resize(at + 3 * mesh.indices.size());
    g.tri_normals.resize(at + 3 * mesh.indices.size());
    write_mesh_corners(mesh, o, g.tri_vertices.data() + at, g.tri_normals.data() + at);
    for (size_t t = 0; t < mesh.indices.size(); ++t)
      g.tri_material.push_back(clamp_material(t < mesh.materials.size() ? mesh.materials[t] : 0u));
  }
  g.quad_first_triangle = uint32_t(g.tri_material.size());
  for (const Quad& q : scene.quads) {
    for (vec3 p : quad_triangles(q, o)) g.tri_vertices.push_back(p);
    for (int k = 0; k < 6; ++k) g.tri_normals.push_back(vec3(0.0f));
    g.tri_material.push_back(clamp_material(q.material));
    g.tri_material.push_back(clamp_material(q.material));
  }
  for (const Sphere& s : scene.spheres) {
    g.spheres.push_back({s.center - o, s.radius});
    g.sphere_material.push_back(clamp_material(s.material));
  }
  g.scale = render_scale(bounds);
  apply_scale(g);
  for (uint32_t t = 0; t < g.triangle_count(); ++t) {
    const vec3* v = &g.tri_vertices[3 * t];
    vec3 c = glm::cross(v[1] - v[0], v[2] - v[0]);
    if (!(glm::dot(c, c) > 0.0f)) ++g.degenerate_triangles;
  }
  compute_triangle_shading(g);
  g.trace = make_trace_geometry(g.tri_vertices, g.spheres, options);
  return geo;
}

RenderScene make_render_scene(const Scene& scene, std::shared_ptr<const RenderGeometry> geo, AutoPilot pilot) {
  RenderScene rs;
  rs.geo = std::move(geo);
  rs.materials = scene.materials;
  if (rs.materials.empty()) rs.materials.push_back(Material{"default"});
  rs.background = scene.background.value_or(vec3(0.0f));
  rs.camera = scene.camera.value_or(Camera{});
  rs.camera.eye = to_render_point(*rs.geo, rs.camera.eye);
  rs.camera.target = to_render_point(*rs.geo, rs.camera.target);
  rebuild_lights(rs);
  if (pilot == AutoPilot::now) update_auto_light_sampling(rs);
  else rs.auto_pilot_pending = true;
  return rs;
}

RenderScene make_render_scene(const Scene& scene, const BvhBuildOptions& bvh_options) {
  return make_render_scene(scene, make_render_geometry(scene, bvh_options));
}

std::shared_ptr<const RenderGeometry> refit_render_geometry(const RenderGeometry& geo, const Scene& scene) {
  auto out = std::make_shared<RenderGeometry>(geo);
  RenderGeometry& g = *out;
  if (scene.triangle_count() != g.triangle_count() || scene.spheres.size() != g.spheres.size()) return out;
  const vec3 o = g.origin;
  vec3* v = g.tri_vertices.data();
  vec3* n = g.tri_normals.data();
  for (const Mesh& mesh : scene.meshes) {  // as make_render_geometry, so a refit equals a rebuild
    write_mesh_corners(mesh, o, v, n);
    v += 3 * mesh.indices.size();
    n += 3 * mesh.indices.size();
  }
  for (const Quad& q : scene.quads)
    for (vec3 p : quad_triangles(q, o)) *v++ = p;
  for (size_t s = 0; s < scene.spheres.size(); ++s)
    g.spheres[s] = {scene.spheres[s].center - o, scene.spheres[s].radius};
  apply_scale(g);  // the build's scale, so a refit equals a rebuild
  compute_triangle_shading(g);
  refit_trace_geometry(g.trace, g.tri_vertices, g.spheres);
  return out;
}

SurfaceHit make_surface_hit(const RenderScene& rs, const Ray& ray, const Hit& hit) {
  const RenderGeometry& g = *rs.geo;
  SurfaceHit sh;
  if (hit.prim < g.triangle_count()) {
    const uint32_t t = hit.prim;
    // The vertices from the leaf block the traversal just tested, if the hit says where: tri_vertices[3 t] is a
    // cache miss on a large mesh (three quarters of this function's time on the bunny with 1-sample frames).
    vec3 v[3];
    for (int k = 0; k < 3; ++k) v[k] = hit.vertices ? lane_vertex(hit.vertices, k) : g.tri_vertices[3 * t + k];
    float b0 = 1.0f - hit.b1 - hit.b2;
    vec3 p = b0 * v[0] + hit.b1 * v[1] + hit.b2 * v[2];
    vec3 err = gamma_bound(7) * (glm::abs(b0 * v[0]) + glm::abs(hit.b1 * v[1]) + glm::abs(hit.b2 * v[2]));
    const TriangleShading& ts = g.tri_shading[t];
    const vec3 ng = ts.valid_ng ? ts.ng : -ray.dir;
    sh.sp = {p, err, ng};
    sh.ns = ng;
    if (ts.has_normals) {  // (without, the interpolation below would give zero, whose fallback is ng too)
      const vec3* n = &g.tri_normals[3 * t];
      vec3 ns = b0 * n[0] + hit.b1 * n[1] + hit.b2 * n[2];
      float ns_len = glm::length(ns);
      if (ns_len > 1e-6f && std::isfinite(ns_len)) sh.ns = ns / ns_len;
      if (glm::dot(sh.ns, ng) < 0.0f) sh.ns = -sh.ns;
    }
    sh.material = g.tri_material[t];
    sh.light = rs.tri_light[t];
    sh.unlit_sides = rs.tri_unlit_sides[t];
  } else {
    const uint32_t s = hit.prim - g.triangle_count();
    const SphereShape& sphere = g.spheres[s];
    vec3 p = ray.org + hit.t * ray.dir;
    vec3 d = p - sphere.center;
    float len = glm::length(d);
    vec3 ng = len > 0.0f ? d / len : -ray.dir;
    p = sphere.center + sphere.radius * ng;  // reproject onto the surface (pbrt-v4 section 6.8.5)
    // p = c + r n: its error is bounded by both terms, not by |p|, which is small where a large sphere passes
    // near the origin (pbrt-v4 section 6.8.5 bounds it in object space, where |p| = r).
    sh.sp = {p, gamma_bound(5) * (glm::abs(sphere.center) + glm::abs(sphere.radius * ng)), ng};
    sh.ns = ng;
    sh.material = g.sphere_material[s];
    sh.light = rs.sphere_light[s];
  }
  return sh;
}

}  // namespace pt
