#pragma once
/// The scene as described by a file: plain structs, integer indices, no behaviour. The render layer turns this into
/// what it traces (BVH, light list); the viewer edits it and asks for a rebuild of only what changed.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/aabb.h"
#include "core/math.h"
#include "core/name_table.h"
#include "core/sphere.h"

namespace pt {

enum class MaterialType : uint8_t { diffuse, specular, glass };
/// The names of material types: JSON "type", the viewer's combo and script, the scene writer.
inline constexpr EnumName<MaterialType> kMaterialTypeNames[] = {
    {MaterialType::diffuse, "diffuse"}, {MaterialType::specular, "specular"}, {MaterialType::glass, "glass"}};
inline const char* name_of(MaterialType v) { return name_of<MaterialType>(kMaterialTypeNames, v); }

/// What a material type reads of Material's parameters, and whether it scatters only into delta directions (then a
/// light cannot be sampled at it and the integrator needs its all-materials kernel). With the name table above,
/// this is the only place outside the type's BSDF (render/bsdf.*) that a new material type is added to: the
/// viewer's panel and edit normalization, the scene writer and the kernel choice all read it. (Importers that map a
/// foreign format's materials, MTL and glTF, choose a type only if that format can express it.)
struct MaterialTypeInfo {
  MaterialType type;
  bool uses_albedo;  ///< albedo is the type's colour (else it is ignored and kept at 1)
  bool uses_ior;     ///< ior is read
  bool delta;        ///< scatters into delta directions only
};
inline constexpr MaterialTypeInfo kMaterialTypeInfo[] = {
    {MaterialType::diffuse, true, false, false},
    {MaterialType::specular, true, false, true},
    {MaterialType::glass, false, true, true}};
constexpr const MaterialTypeInfo& info_of(MaterialType t) {
  for (const MaterialTypeInfo& i : kMaterialTypeInfo)
    if (i.type == t) return i;
  return kMaterialTypeInfo[0];
}

/// A surface material. Every surface scatters on both sides; emission leaves the front side only.
struct Material {
  std::string name;
  MaterialType type = MaterialType::diffuse;
  vec3 albedo{0.8f};    ///< diffuse reflectance, or mirror tint for specular
  float ior = 1.5f;     ///< glass only: index of refraction inside / outside
  vec3 emission{0.0f};  ///< emitted radiance (W / m^2 / sr), front side only
  bool emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
  bool operator==(const Material&) const = default;
};

/// Pinhole camera; the exact ray model is in render/camera.h (and README).
struct Camera {
  vec3 eye{0.0f, 0.0f, 5.0f};
  vec3 target{0.0f};
  vec3 up{0.0f, 1.0f, 0.0f};
  float fov_deg = 40.0f;  ///< vertical field of view
  bool operator==(const Camera&) const = default;
};

struct Sphere : SphereShape {
  uint32_t material = 0;
};

/// A parallelogram {corner + a edge1 + b edge2 : a, b in [0,1]}; front normal = normalize(cross(edge1, edge2)).
/// An emissive quad is a rectangle light.
struct Quad {
  vec3 corner{0.0f};
  vec3 edge1{1.0f, 0.0f, 0.0f};
  vec3 edge2{0.0f, 1.0f, 0.0f};
  uint32_t material = 0;
};

/// The two triangles of a quad, (c, c+e1, c+e2) and (c+e1+e2, c+e2, c+e1): the winding of cross(e1, e2), and the
/// first triangle's edges are the quad's edges. `offset` is subtracted from every corner.
inline std::array<vec3, 6> quad_triangles(const Quad& q, vec3 offset = vec3(0.0f)) {
  vec3 c = q.corner - offset, a = c + q.edge1, b = c + q.edge2, d = c + q.edge1 + q.edge2;
  return {c, a, b, d, b, a};
}

/// Where a mesh came from, so a saved scene (scene/save_json.h) can name its file instead of copying it.
struct MeshSource {
  std::string file;             ///< absolute path of the OBJ it was read from; empty: generated, or edited since
  bool file_materials = false;  ///< its faces use the file's MTL materials (no "material" override)
  vec3 scale{1.0f}, axis{0.0f, 1.0f, 0.0f}, translate{0.0f};  ///< the JSON transform, as written
  float degrees = 0.0f;
};

/// A triangle mesh. Front side: counter-clockwise winding.
struct Mesh {
  MeshSource source;
  std::string name;                    ///< file or object name, for messages and the viewer
  /// Positions are relative to this point, which is kept in double: a small mesh translated far from the world
  /// origin keeps float precision relative to its own size. (In world-space floats a unit mesh at 1e5 snaps to a
  /// 1/128 grid, its thin triangles fold over, and a path spawned on a folded triangle leaves the mesh: issue 13.)
  dvec3 origin{0.0};
  std::vector<vec3> positions;
  std::vector<uvec3> indices;          ///< one per triangle, into positions
  std::vector<vec3> normals;           ///< optional shading normals
  std::vector<uvec3> normal_indices;   ///< empty, or one per triangle into normals
  std::vector<uint32_t> materials;     ///< one per triangle, into Scene::materials

  /// World-space position of vertex i, rounded to float once.
  vec3 world_position(uint32_t i) const { return vec3(origin + dvec3(positions[i])); }
};

struct Scene {
  std::string source;                  ///< the file it came from, or "builtin:NAME"
  std::optional<Camera> camera;        ///< absent: frame the bounds (see finalize_scene)
  std::vector<Camera> cameras;         ///< the cameras a file defines (glTF), for --camera N; may be empty
  std::optional<vec3> background;      ///< constant radiance of escaping rays; absent means black
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Sphere> spheres;
  std::vector<Quad> quads;
  std::vector<std::string> warnings;   ///< recoverable oddities met while loading

  size_t triangle_count() const {
    size_t n = 2 * quads.size();
    for (const Mesh& m : meshes) n += m.indices.size();
    return n;
  }
  AABB bounds() const;
  bool has_emitter() const;
};

/// A camera on the +z side of `bounds` looking down -z at their center, far enough that their bounding sphere fits
/// a 40-degree vertical field of view with a 10% margin; up is +y. Empty or non-finite bounds give Camera{}.
Camera framing_camera(const AABB& bounds);

/// Makes scene.cameras[index] the scene's camera (--camera N); returns "" or why it cannot.
std::string select_camera(Scene& scene, size_t index);

/// Gives a scene what it needs to render and did not say: a camera framing its bounds when it has none, and a
/// rectangle light above its bounds (with a warning) when it has no emitter and no background.
void finalize_scene(Scene& scene);

}  // namespace pt
