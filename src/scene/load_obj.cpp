/// Wavefront OBJ (with MTL materials) as a triangle mesh.
///
/// OBJ / MTL mapping (README "OBJ / MTL mapping"; material_from_mtl in mtl.h applies it):
///   Kd -> diffuse albedo (0.8 grey when absent); Ke -> emission (front side: counter-clockwise winding);
///   illum 3 or 5, or Ks dominant over Kd with Ns >= 500 -> mirror (specular) with albedo Ks;
///   illum 4, 6 or 7, or d < 1 / Tr > 0 -> glass with ior = Ni (1.5 when Ni is absent or <= 0);
///   an explicit illum 3/5/4/6/7 decides before d/Tr, and transparency before Ks dominance.
///   Faces without a material, with a material no library defines, or whose .mtl is missing or unreadable (a
///   warning), get diffuse 0.8 grey ("default"). Materials are named as in the MTL; only those some face uses are
///   added to the scene, and a name already taken by a different material gets a "#2"-style suffix. A name defined
///   again, in the same library or a later one, keeps its first definition (as tinyobjloader does), with a warning.
/// Geometry: shading normals from vn where a face gives them for all its corners (faces that do not get their flat
/// normal when others do); polygons are triangulated keeping their winding (polygon.h); zero-area triangles are
/// dropped with one warning giving their count and the line of the first.
///
/// tinyobjloader parses the file, after our own validation pass (obj_scan.h) so that every error carries its line:
/// tinyobjloader reads "v 1 abc" as zeros and skips out-of-range faces. The MTL is parsed by mtl.cpp for the same
/// reason. Errors: "FILE:LINE: reason", or "FILE: reason" ("cannot open", "no triangles").
#include <tiny_obj_loader.h>

#include <filesystem>
#include <istream>
#include <streambuf>
#include <unordered_map>

#include "scene/load_internal.h"
#include "scene/mtl.h"
#include "scene/obj_scan.h"
#include "scene/polygon.h"

namespace pt {

namespace {

/// A read-only istream over memory, so tinyobjloader reads the text without another copy of the file.
struct MemoryBuffer : std::streambuf {
  explicit MemoryBuffer(std::string_view text) {
    char* p = const_cast<char*>(text.data());  // the get area is never written through
    setg(p, p, p + text.size());
  }
};

/// The materials the OBJ's libraries define, by name (the first definition of a name wins, as in tinyobjloader).
struct Libraries {
  std::vector<Material> materials;
  std::unordered_map<std::string, uint32_t> by_name;
  bool all_loaded = true;
};

Result<Libraries> load_libraries(const std::string& path, const ObjScan& scan, std::vector<std::string>& warnings) {
  Libraries libs;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (const ObjLibraryRef& ref : scan.libraries) {
    std::filesystem::path file(ref.file);
    if (file.is_relative()) file = dir / file;
    Result<std::string> text = read_text_file(file.lexically_normal().string());
    if (!text) {
      libs.all_loaded = false;
      warnings.push_back(located(path, ref.line) + "material library " + text.error() +
                         " (its materials become diffuse 0.8 grey)");
      continue;
    }
    Result<MtlLibrary> lib = parse_mtl(join_continued_lines(std::move(*text)), file.lexically_normal().string());
    if (!lib) return Error{located(path, ref.line) + "material library " + lib.error()};
    for (std::string& w : lib->warnings) warnings.push_back(std::move(w));
    for (Material& m : lib->materials) {
      if (!libs.by_name.try_emplace(m.name, uint32_t(libs.materials.size())).second) {
        warnings.push_back(located(path, ref.line) + "material library " + file.lexically_normal().string() +
                           " defines '" + m.name + "' again: the first definition is used");
        continue;
      }
      libs.materials.push_back(std::move(m));
    }
  }
  return libs;
}

/// The text tinyobjloader gets: ours, or without comments after statements (it would read "f 1 2 3 # x" as a
/// fourth corner and fail).
std::string without_inline_comments(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for_each_line(text, [&](int, std::string_view line) {
    out += line.substr(0, comment_start(line));
    out += '\n';
    return true;
  });
  return out;
}

/// Drops the positions and normals no triangle uses (stray points, corners of dropped triangles), so a mesh's
/// bounds are those of its surface.
void compact(Mesh& mesh) {
  auto remap = [](std::vector<vec3>& values, std::vector<uvec3>& triangles) {
    constexpr uint32_t kUnused = ~0u;
    std::vector<uint32_t> index(values.size(), kUnused);
    std::vector<vec3> kept;
    kept.reserve(values.size());
    for (uvec3& t : triangles)
      for (int k = 0; k < 3; ++k) {
        uint32_t& i = index[t[k]];
        if (i == kUnused) {
          i = uint32_t(kept.size());
          kept.push_back(values[t[k]]);
        }
        t[k] = i;
      }
    values = std::move(kept);
  };
  remap(mesh.positions, mesh.indices);
  remap(mesh.normals, mesh.normal_indices);
}

}  // namespace

Result<ObjData> read_obj(const std::string& path, bool use_mtl) {
  Result<std::string> text = read_text_file(path);
  if (!text) return Error{text.error()};
  *text = join_continued_lines(std::move(*text));  // both passes below read the joined lines
  Result<ObjScan> scanned = scan_obj(*text, path);
  if (!scanned) return Error{scanned.error()};
  const ObjScan& scan = *scanned;
  if (scan.faces.empty()) return Error{path + ": no triangles (the file has no faces)"};

  ObjData out;
  Libraries libs;
  if (use_mtl) {
    Result<Libraries> loaded = load_libraries(path, scan, out.warnings);
    if (!loaded) return Error{loaded.error()};
    libs = std::move(*loaded);
  }

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> unused_materials;
  std::string tiny_warning, tiny_error;
  bool parsed = false;
  try {
    std::string cleaned = scan.has_inline_comments ? without_inline_comments(*text) : std::string();
    MemoryBuffer buffer(scan.has_inline_comments ? std::string_view(cleaned) : std::string_view(*text));
    std::istream stream(&buffer);
    // No material reader: mtl.cpp has read the libraries. No triangulation: polygon.cpp keeps the winding.
    parsed = tinyobj::LoadObj(&attrib, &shapes, &unused_materials, &tiny_warning, &tiny_error, &stream, nullptr,
                              /*triangulate=*/false, /*default_vcols_fallback=*/false);
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
  if (!parsed) return Error{path + ": " + (tiny_error.empty() ? std::string("cannot parse") : tiny_error)};
  size_t tiny_faces = 0;
  for (const tinyobj::shape_t& s : shapes) tiny_faces += s.mesh.num_face_vertices.size();
  if (attrib.vertices.size() != 3 * scan.positions || attrib.normals.size() != 3 * scan.normals ||
      tiny_faces != scan.faces.size())
    return Error{path + ": tinyobjloader read " + std::to_string(attrib.vertices.size() / 3) + " vertices and " +
                 std::to_string(tiny_faces) + " faces where there are " + std::to_string(scan.positions) + " and " +
                 std::to_string(scan.faces.size())};

  Mesh& mesh = out.mesh;
  mesh.name = path;
  mesh.positions.resize(scan.positions);
  for (size_t i = 0; i < scan.positions; ++i)
    mesh.positions[i] = vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
  mesh.normals.resize(scan.normals);
  std::vector<bool> normal_ok(scan.normals);
  for (size_t i = 0; i < scan.normals; ++i) {
    vec3 n(attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2]);
    float len = glm::length(n);
    normal_ok[i] = len > 0.0f && std::isfinite(len);
    mesh.normals[i] = normal_ok[i] ? n / len : vec3(0.0f);
  }

  // Material of each usemtl slot: a library material (added on first use) or the default grey.
  std::vector<int> slot_material(scan.materials.size(), -1);
  int default_material = -1;
  auto material_for = [&](int slot) -> uint32_t {
    if (!use_mtl) return 0;
    int& id = slot >= 0 ? slot_material[size_t(slot)] : default_material;
    if (id >= 0) return uint32_t(id);
    auto it = slot >= 0 ? libs.by_name.find(scan.materials[size_t(slot)].name) : libs.by_name.end();
    if (it != libs.by_name.end()) {
      out.materials.push_back(libs.materials[it->second]);
      id = int(out.materials.size() - 1);
      return uint32_t(id);
    }
    if (slot >= 0 && libs.all_loaded) {
      const ObjMaterialUse& use = scan.materials[size_t(slot)];
      out.warnings.push_back(located(path, use.line) + "material '" + use.name +
                             "' is not defined by any material library: using diffuse 0.8 grey");
    }
    if (default_material < 0) {
      out.materials.push_back(Material{"default"});
      default_material = int(out.materials.size() - 1);
    }
    id = default_material;
    return uint32_t(id);
  };

  constexpr uint32_t kNoNormal = ~0u;
  std::vector<vec3> corners;
  std::vector<uvec3> local;
  size_t face = 0, degenerate = 0;
  int first_degenerate_line = 0;
  bool any_normals = false;
  for (const tinyobj::shape_t& shape : shapes) {
    size_t offset = 0;
    for (unsigned char count : shape.mesh.num_face_vertices) {
      const ObjFace& f = scan.faces[face++];
      const tinyobj::index_t* idx = &shape.mesh.indices[offset];
      offset += count;
      if (count != f.corners)
        return Error{located(path, f.line) + "tinyobjloader read " + std::to_string(count) + " corners"};
      corners.resize(count);
      for (size_t k = 0; k < count; ++k) corners[k] = mesh.positions[size_t(idx[k].vertex_index)];
      local.clear();
      triangulate_polygon(corners, local);
      uint32_t material = material_for(f.material);
      for (uvec3 t : local) {
        uvec3 tri(uint32_t(idx[t.x].vertex_index), uint32_t(idx[t.y].vertex_index), uint32_t(idx[t.z].vertex_index));
        dvec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
        dvec3 n = glm::cross(b - a, c - a);
        if (!(glm::dot(n, n) > 0.0)) {
          if (degenerate++ == 0) first_degenerate_line = f.line;
          continue;
        }
        uvec3 ntri(kNoNormal);
        int na = idx[t.x].normal_index, nb = idx[t.y].normal_index, nc = idx[t.z].normal_index;
        if (na >= 0 && nb >= 0 && nc >= 0 && normal_ok[size_t(na)] && normal_ok[size_t(nb)] && normal_ok[size_t(nc)]) {
          ntri = uvec3(uint32_t(na), uint32_t(nb), uint32_t(nc));
          any_normals = true;
        }
        mesh.indices.push_back(tri);
        mesh.normal_indices.push_back(ntri);
        mesh.materials.push_back(material);
      }
    }
  }
  if (degenerate > 0)
    out.warnings.push_back(located(path, first_degenerate_line) + std::to_string(degenerate) +
                           " degenerate (zero-area) triangle" + (degenerate == 1 ? "" : "s") +
                           " dropped (the first from this line)");
  if (mesh.indices.empty()) return Error{path + ": no triangles with non-zero area"};
  if (!any_normals) {
    mesh.normals.clear();
    mesh.normal_indices.clear();
  } else {
    // Faces without (valid) normals in a mesh that has them shade flat: give them their geometric normal.
    for (size_t t = 0; t < mesh.indices.size(); ++t) {
      if (mesh.normal_indices[t].x != kNoNormal) continue;
      uvec3 tri = mesh.indices[t];
      dvec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
      vec3 n(glm::normalize(glm::cross(b - a, c - a)));  // non-zero: degenerate triangles are gone
      mesh.normal_indices[t] = uvec3(uint32_t(mesh.normals.size()));
      mesh.normals.push_back(n);
    }
  }
  compact(mesh);
  return out;
}

void append_obj(Scene& scene, ObjData obj, int override_material) {
  Mesh& mesh = obj.mesh;
  if (override_material >= 0) {
    mesh.materials.assign(mesh.indices.size(), uint32_t(override_material));
  } else {
    if (obj.materials.empty()) obj.materials.push_back(Material{"default"});
    std::vector<uint32_t> ids;
    ids.reserve(obj.materials.size());
    for (Material& m : obj.materials) ids.push_back(add_material(scene, std::move(m)));
    mesh.materials.resize(mesh.indices.size(), 0u);
    for (uint32_t& m : mesh.materials) m = ids[m < ids.size() ? m : 0u];
  }
  for (std::string& w : obj.warnings) scene.warnings.push_back(std::move(w));
  scene.meshes.push_back(std::move(mesh));
}

}  // namespace pt
