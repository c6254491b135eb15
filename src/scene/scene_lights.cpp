#include "scene/scene_lights.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <numeric>
#include <tuple>

namespace pt {

namespace {

bool emissive(const Scene& scene, uint32_t material) {
  return material < scene.materials.size() && scene.materials[material].emissive();
}

/// Union-find over a mesh's emissive triangles.
struct Groups {
  std::vector<uint32_t> parent;
  explicit Groups(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

void add_mesh_lights(const Scene& scene, uint32_t mesh_index, std::vector<SceneLight>& out) {
  const Mesh& mesh = scene.meshes[mesh_index];
  std::vector<uint32_t> tris;
  for (uint32_t t = 0; t < mesh.indices.size(); ++t)
    if (emissive(scene, t < mesh.materials.size() ? mesh.materials[t] : 0u)) tris.push_back(t);
  if (tris.empty()) return;
  auto material = [&](uint32_t t) { return t < mesh.materials.size() ? mesh.materials[t] : 0u; };
  // Triangles meet where they share a vertex: the same index, or the same position under another index.
  Groups groups(tris.size());
  std::map<std::tuple<float, float, float, uint32_t>, uint32_t> first_at;  // (position, material) -> group slot
  for (uint32_t i = 0; i < tris.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      vec3 p = mesh.positions[mesh.indices[tris[i]][k]];
      auto [it, inserted] = first_at.try_emplace({p.x, p.y, p.z, material(tris[i])}, i);
      if (!inserted) groups.join(i, it->second);
    }
  std::map<uint32_t, size_t> light_of_root;
  for (uint32_t i = 0; i < tris.size(); ++i) {
    uint32_t root = groups.find(i);
    auto [it, inserted] = light_of_root.try_emplace(root, out.size());
    if (inserted) out.push_back({SceneLightKind::triangles, mesh_index, {}, material(tris[i])});
    out[it->second].triangles.push_back(tris[i]);
  }
}

/// The distinct vertex indices of a triangle light.
std::vector<uint32_t> light_vertices(const Mesh& mesh, const SceneLight& light) {
  std::vector<uint32_t> v;
  for (uint32_t t : light.triangles)
    for (int k = 0; k < 3; ++k) v.push_back(mesh.indices[t][k]);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

/// Gives the light's triangles vertices of their own where other triangles share them, so moving the light never
/// drags a neighbouring surface along. Appends positions; the triangle count does not change.
void detach_vertices(Mesh& mesh, const SceneLight& light) {
  std::vector<bool> in_light(mesh.indices.size(), false);
  for (uint32_t t : light.triangles) in_light[t] = true;
  std::vector<bool> shared(mesh.positions.size(), false);
  for (size_t t = 0; t < mesh.indices.size(); ++t)
    if (!in_light[t])
      for (int k = 0; k < 3; ++k) shared[mesh.indices[t][k]] = true;
  std::map<uint32_t, uint32_t> copy_of;
  for (uint32_t t : light.triangles)
    for (int k = 0; k < 3; ++k) {
      uint32_t& idx = mesh.indices[t][k];
      if (!shared[idx]) continue;
      auto [it, inserted] = copy_of.try_emplace(idx, uint32_t(mesh.positions.size()));
      if (inserted) mesh.positions.push_back(mesh.positions[idx]);
      idx = it->second;
    }
}

/// Applies `f` to every vertex of the light (triangles) after detaching them.
template <class F>
void transform_triangle_light(Scene& scene, const SceneLight& light, F&& f) {
  Mesh& mesh = scene.meshes[light.shape];
  mesh.source.file.clear();  // no longer what its file describes: a saved scene writes the mesh out
  detach_vertices(mesh, light);
  for (uint32_t i : light_vertices(mesh, light)) mesh.positions[i] = f(mesh.positions[i]);
}

/// Coordinates (a, b) of the in-plane part of d = a u + b v (+ out of plane), for unit u, v.
vec2 frame_coords(vec3 d, vec3 u, vec3 v) {
  float uv = glm::dot(u, v), du = glm::dot(d, u), dv = glm::dot(d, v), det = 1.0f - uv * uv;
  return det > 1e-12f ? vec2((du - dv * uv) / det, (dv - du * uv) / det) : vec2(du, dv);
}

LightPlacement triangle_placement(const Mesh& mesh, const SceneLight& light) {
  LightPlacement pl;
  // Areas and normals in double: their float squares vanish for a light 1e-10 across and overflow at 1e19.
  dvec3 normal(0.0), centroid(0.0);
  double area = 0.0;
  std::map<std::pair<uint32_t, uint32_t>, int> edge_count;
  for (uint32_t t : light.triangles) {
    uvec3 idx = mesh.indices[t];
    const dvec3 a(mesh.positions[idx[0]]), b(mesh.positions[idx[1]]), c(mesh.positions[idx[2]]);
    const dvec3 cr = glm::cross(b - a, c - a);
    const double ta = 0.5 * glm::length(cr);
    normal += cr;
    centroid += ta * (a + b + c) / 3.0;
    area += ta;
    for (int k = 0; k < 3; ++k) {
      uint32_t i = idx[k], j = idx[(k + 1) % 3];
      ++edge_count[{std::min(i, j), std::max(i, j)}];
    }
  }
  pl.center = area > 0.0 ? vec3(centroid / area) : mesh.positions[mesh.indices[light.triangles[0]][0]];
  const double nl = glm::length(normal);
  const vec3 n = nl > 0.0 ? vec3(normal / nl) : vec3(0, 1, 0);
  const dvec3 dn(n);
  // Boundary edges (used once) in the triangles' order: a parallelogram's sides, never its diagonal.
  std::vector<vec3> dirs;
  for (uint32_t t : light.triangles)
    for (int k = 0; k < 3; ++k) {
      uint32_t i = mesh.indices[t][k], j = mesh.indices[t][(k + 1) % 3];
      if (edge_count[{std::min(i, j), std::max(i, j)}] != 1) continue;
      dvec3 d = dvec3(mesh.positions[j]) - dvec3(mesh.positions[i]);
      d -= glm::dot(d, dn) * dn;
      const double len = glm::length(d);
      if (len > 0.0) dirs.push_back(vec3(d / len));
    }
  if (dirs.empty()) return pl;
  pl.u = dirs[0];
  pl.v = glm::normalize(glm::cross(n, pl.u));
  for (vec3 d : dirs)
    if (glm::length(glm::cross(d, pl.u)) > 0.1f) {
      pl.v = d;
      break;
    }
  vec2 lo(INFINITY), hi(-INFINITY);
  for (uint32_t i : light_vertices(mesh, light)) {
    vec2 ab = frame_coords(mesh.positions[i] - pl.center, pl.u, pl.v);
    lo = glm::min(lo, ab);
    hi = glm::max(hi, ab);
  }
  pl.size = hi - lo;
  return pl;
}

}  // namespace

std::vector<SceneLight> find_scene_lights(const Scene& scene) {
  std::vector<SceneLight> out;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) add_mesh_lights(scene, m, out);
  for (uint32_t q = 0; q < scene.quads.size(); ++q)
    if (emissive(scene, scene.quads[q].material)) out.push_back({SceneLightKind::quad, q, {}, scene.quads[q].material});
  for (uint32_t s = 0; s < scene.spheres.size(); ++s)
    if (emissive(scene, scene.spheres[s].material))
      out.push_back({SceneLightKind::sphere, s, {}, scene.spheres[s].material});
  return out;
}

std::vector<SceneLight> find_scene_lights(const Scene& scene, const std::vector<SceneLight>& before) {
  std::vector<SceneLight> out = find_scene_lights(scene);
  for (const SceneLight& l : before)
    if (!emissive(scene, l.material)) out.push_back(l);
  // find_scene_lights's order: mesh groups by mesh and first triangle, then quads, then spheres.
  auto key = [](const SceneLight& l) {
    const int rank = l.kind == SceneLightKind::triangles ? 0 : l.kind == SceneLightKind::quad ? 1 : 2;
    return std::tuple(rank, l.shape, l.triangles.empty() ? 0u : l.triangles.front());
  };
  std::stable_sort(out.begin(), out.end(), [&](const SceneLight& a, const SceneLight& b) { return key(a) < key(b); });
  return out;
}

LightPlacement light_placement(const Scene& scene, const SceneLight& light) {
  LightPlacement pl;
  switch (light.kind) {
    case SceneLightKind::quad: {
      const Quad& q = scene.quads[light.shape];
      pl.center = q.corner + 0.5f * (q.edge1 + q.edge2);
      pl.size = vec2(glm::length(q.edge1), glm::length(q.edge2));
      if (pl.size.x > 0.0f) pl.u = q.edge1 / pl.size.x;
      if (pl.size.y > 0.0f) pl.v = q.edge2 / pl.size.y;
      return pl;
    }
    case SceneLightKind::sphere: {
      const Sphere& s = scene.spheres[light.shape];
      pl.center = s.center;
      pl.size = vec2(2.0f * s.radius);
      return pl;
    }
    case SceneLightKind::triangles: {
      // Mesh positions are relative to the mesh's origin (kept in double); the placement is in world space.
      const Mesh& mesh = scene.meshes[light.shape];
      pl = triangle_placement(mesh, light);
      pl.center = vec3(mesh.origin + dvec3(pl.center));
      return pl;
    }
  }
  return pl;
}

/// A light's placement in the frame its shape stores coordinates in: the mesh's (origin-relative) frame for
/// triangles, world space for quads and spheres. Resizing and scaling work about the center in that frame.
static LightPlacement stored_placement(const Scene& scene, const SceneLight& light) {
  if (light.kind == SceneLightKind::triangles) return triangle_placement(scene.meshes[light.shape], light);
  return light_placement(scene, light);
}

std::string light_label(const Scene& scene, const SceneLight& light) {
  std::string name = light.material < scene.materials.size() ? scene.materials[light.material].name : "?";
  LightPlacement pl = light_placement(scene, light);
  char buf[160];
  if (light.kind == SceneLightKind::sphere)
    std::snprintf(buf, sizeof buf, "%s (sphere r %.3g)", name.c_str(), 0.5f * pl.size.x);
  else if (light.kind == SceneLightKind::quad) {
    const auto& q = scene.quads[light.shape];
    std::snprintf(buf, sizeof buf, "%s (%s %.3g x %.3g)", name.c_str(),
                  at_right_angle(q.edge1, q.edge2) ? "rectangle" : "parallelogram", pl.size.x, pl.size.y);
  }
  else
    std::snprintf(buf, sizeof buf, "%s (%zu triangles %.3g x %.3g)", name.c_str(), light.triangles.size(), pl.size.x,
                  pl.size.y);
  return buf;
}

void move_light(Scene& scene, SceneLight& light, vec3 center) {
  vec3 delta = center - light_placement(scene, light).center;
  if (!is_finite(delta)) return;
  switch (light.kind) {
    case SceneLightKind::quad: scene.quads[light.shape].corner += delta; break;
    case SceneLightKind::sphere: scene.spheres[light.shape].center += delta; break;
    case SceneLightKind::triangles: transform_triangle_light(scene, light, [&](vec3 p) { return p + delta; }); break;
  }
}

bool resize_light(Scene& scene, SceneLight& light, vec2 size) {
  if (light.kind == SceneLightKind::sphere || !(size.x > 0.0f) || !(size.y > 0.0f) || !is_finite(vec3(size, 0.0f)))
    return false;
  LightPlacement pl = stored_placement(scene, light);
  if (light.kind == SceneLightKind::quad) {
    Quad& q = scene.quads[light.shape];
    q.edge1 = pl.u * size.x;
    q.edge2 = pl.v * size.y;
    q.corner = pl.center - 0.5f * (q.edge1 + q.edge2);
    return true;
  }
  if (!(pl.size.x > 0.0f) || !(pl.size.y > 0.0f)) return false;
  vec2 k = size / pl.size;
  vec3 n = glm::normalize(glm::cross(pl.u, pl.v));
  transform_triangle_light(scene, light, [&](vec3 p) {
    vec3 d = p - pl.center;
    vec2 ab = frame_coords(d, pl.u, pl.v) * k;
    return pl.center + ab.x * pl.u + ab.y * pl.v + glm::dot(d, n) * n;
  });
  return true;
}

bool scale_light(Scene& scene, SceneLight& light, float factor) {
  if (!(factor > 0.0f) || !std::isfinite(factor)) return false;
  LightPlacement pl = stored_placement(scene, light);
  switch (light.kind) {
    case SceneLightKind::quad: {
      Quad& q = scene.quads[light.shape];
      q.edge1 *= factor;
      q.edge2 *= factor;
      q.corner = pl.center - 0.5f * (q.edge1 + q.edge2);
      break;
    }
    case SceneLightKind::sphere: scene.spheres[light.shape].radius *= factor; break;
    case SceneLightKind::triangles:
      transform_triangle_light(scene, light, [&](vec3 p) { return pl.center + factor * (p - pl.center); });
      break;
  }
  return true;
}

int light_of_primitive(const Scene& scene, const std::vector<SceneLight>& lights, uint32_t prim) {
  uint32_t first = 0;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    uint32_t n = uint32_t(scene.meshes[m].indices.size());
    if (prim < first + n) {
      for (size_t i = 0; i < lights.size(); ++i)
        if (lights[i].kind == SceneLightKind::triangles && lights[i].shape == m &&
            std::find(lights[i].triangles.begin(), lights[i].triangles.end(), prim - first) !=
                lights[i].triangles.end())
          return int(i);
      return -1;
    }
    first += n;
  }
  auto find = [&](SceneLightKind kind, uint32_t shape) {
    for (size_t i = 0; i < lights.size(); ++i)
      if (lights[i].kind == kind && lights[i].shape == shape) return int(i);
    return -1;
  };
  if (prim < first + 2 * scene.quads.size()) return find(SceneLightKind::quad, (prim - first) / 2);
  return find(SceneLightKind::sphere, prim - first - uint32_t(2 * scene.quads.size()));
}

}  // namespace pt
