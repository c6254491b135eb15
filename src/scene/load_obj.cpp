/// Wavefront OBJ/MTL via tinyobjloader, after our own line-by-line validation so every error names its line.
///
/// MTL mapping (README "OBJ / MTL mapping"):
///   Kd -> diffuse albedo; Ke -> emission;
///   illum 4/6/7, or d < 1 / Tr > 0 -> glass with ior = Ni (1.5 when Ni is absent or 1);
///   illum 3/5, or Ks dominant over Kd with Ns >= 500 -> mirror (specular) with albedo Ks;
///   faces without a material, or a missing .mtl (a warning) -> diffuse 0.8.
/// Shading normals from vn where every corner of a face has one; polygons are triangulated by tinyobjloader.
#include <tiny_obj_loader.h>

#include <charconv>
#include <filesystem>
#include <map>
#include <sstream>

#include "scene/load_internal.h"

namespace pt {

namespace {

bool parse_float(std::string_view s, float& out) {
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size() && std::isfinite(out);
}

bool parse_int(std::string_view s, long long& out) {
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

std::vector<std::string_view> split_ws(std::string_view line) {
  std::vector<std::string_view> parts;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) parts.push_back(line.substr(start, i - start));
  }
  return parts;
}

/// Checks the statements tinyobjloader would accept silently (it reads "v a b c" as zeros and does not check
/// face indices). Returns an error "PATH:LINE: reason" or an empty string.
std::string validate_obj(const std::string& path, std::string_view text) {
  long long counts[3] = {0, 0, 0};  // v, vt, vn
  size_t faces = 0;
  int line_no = 0;
  size_t pos = 0;
  auto fail = [&](const std::string& why) { return path + ":" + std::to_string(line_no) + ": " + why; };
  while (pos <= text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find('\0') != std::string_view::npos) return fail("binary data in a text file");
    if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::vector<std::string_view> parts = split_ws(line);
    if (parts.empty()) continue;
    std::string_view kw = parts[0];
    if (kw == "v" || kw == "vn" || kw == "vt") {
      size_t need = kw == "vt" ? 1 : 3;
      if (parts.size() - 1 < need)
        return fail("'" + std::string(kw) + "' needs " + std::to_string(need) + " numbers");
      for (size_t k = 1; k < parts.size() && k <= (kw == "v" ? 6u : 3u); ++k) {
        float v;
        if (!parse_float(parts[k], v))
          return fail("'" + std::string(kw) + "': '" + std::string(parts[k]) + "' is not a finite number");
      }
      ++counts[kw == "v" ? 0 : kw == "vt" ? 1 : 2];
    } else if (kw == "f") {
      if (parts.size() < 4) return fail("a face needs at least 3 vertices");
      for (size_t k = 1; k < parts.size(); ++k) {
        std::string_view ref = parts[k];
        for (int slot = 0; slot < 3 && !ref.empty(); ++slot) {
          size_t slash = ref.find('/');
          std::string_view idx = ref.substr(0, slash);
          ref = slash == std::string_view::npos ? std::string_view() : ref.substr(slash + 1);
          if (idx.empty() && slot > 0) continue;  // "v//vn"
          long long i;
          if (!parse_int(idx, i)) return fail("face index '" + std::string(idx) + "' is not an integer");
          const char* what[3] = {"vertex", "texture coordinate", "normal"};
          if (i == 0) return fail(std::string("face ") + what[slot] + " index 0 (OBJ indices start at 1)");
          long long n = counts[slot];
          if (i > n || -i > n)
            return fail(std::string("face ") + what[slot] + " index " + std::to_string(i) + " out of range (" +
                        std::to_string(n) + " defined so far)");
        }
      }
      ++faces;
    }
  }
  if (faces == 0) return path + ": no triangles (no 'f' statements)";
  return {};
}

Material convert_material(const tinyobj::material_t& t) {
  Material m;
  m.name = t.name;
  vec3 kd(t.diffuse[0], t.diffuse[1], t.diffuse[2]);
  vec3 ks(t.specular[0], t.specular[1], t.specular[2]);
  m.emission = glm::max(vec3(t.emission[0], t.emission[1], t.emission[2]), vec3(0.0f));
  bool glass = t.illum == 4 || t.illum == 6 || t.illum == 7 || t.dissolve < 1.0f;
  bool mirror = t.illum == 3 || t.illum == 5 || (max_component(ks) > max_component(kd) && t.shininess >= 500.0f);
  if (glass) {
    m.type = MaterialType::glass;
    m.albedo = vec3(1.0f);
    m.ior = (t.ior > 0.0f && t.ior != 1.0f && std::isfinite(t.ior)) ? t.ior : 1.5f;
  } else if (mirror) {
    m.type = MaterialType::specular;
    m.albedo = glm::clamp(ks, vec3(0.0f), vec3(1.0f));
  } else {
    m.albedo = glm::max(kd, vec3(0.0f));
  }
  if (!is_finite(m.albedo)) m.albedo = vec3(0.8f);
  if (!is_finite(m.emission)) m.emission = vec3(0.0f);
  return m;
}

}  // namespace

Result<ObjData> read_obj(const std::string& path, bool use_mtl) {
  Result<std::string> text = read_text_file(path);
  if (!text) return Error{text.error()};
  if (std::string err = validate_obj(path, *text); !err.empty()) return Error{err};

  ObjData out;
  // Gather the material libraries ourselves, so a missing one is a warning that names it and paths are relative
  // to the OBJ; tinyobjloader then parses OBJ and MTL text from memory.
  const std::string dir = std::filesystem::path(path).parent_path().string();
  std::string mtl_text;
  if (use_mtl) {
    size_t pos = 0;
    const std::string& t = *text;
    while (pos < t.size()) {
      size_t end = t.find('\n', pos);
      if (end == std::string::npos) end = t.size();
      std::string_view line(t.data() + pos, end - pos);
      pos = end + 1;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      auto parts = split_ws(line);
      if (parts.size() < 2 || parts[0] != "mtllib") continue;
      for (size_t k = 1; k < parts.size(); ++k) {
        std::filesystem::path lib(parts[k]);
        if (lib.is_relative()) lib = std::filesystem::path(dir) / lib;
        Result<std::string> mtl = read_text_file(lib.string());
        if (!mtl) {
          out.warnings.push_back(path + ": material library " + mtl.error() + "; using diffuse 0.8");
          continue;
        }
        mtl_text += *mtl;
        mtl_text += "\n";
      }
    }
  }
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  bool ok = false;
  try {
    ok = reader.ParseFromString(*text, mtl_text, config);
  } catch (...) {
    ok = false;
  }
  if (!ok) return Error{path + ": " + (reader.Error().empty() ? "cannot parse" : reader.Error())};
  const std::vector<tinyobj::material_t>& materials = reader.GetMaterials();
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  Mesh& mesh = out.mesh;
  mesh.name = path;
  for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
    mesh.positions.emplace_back(attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]);
  for (size_t i = 0; i + 2 < attrib.normals.size(); i += 3)
    mesh.normals.emplace_back(attrib.normals[i], attrib.normals[i + 1], attrib.normals[i + 2]);
  for (const tinyobj::material_t& m : materials) out.materials.push_back(convert_material(m));
  int default_id = -1;
  size_t degenerate = 0;
  bool any_normals = false;
  std::vector<uvec3> normal_idx;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& idx = shape.mesh.indices;
    for (size_t f = 0; f + 2 < idx.size(); f += 3) {
      size_t face = f / 3;
      uvec3 tri(uint32_t(idx[f].vertex_index), uint32_t(idx[f + 1].vertex_index), uint32_t(idx[f + 2].vertex_index));
      vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y], c = mesh.positions[tri.z];
      vec3 cr = glm::cross(b - a, c - a);
      if (!(glm::dot(cr, cr) > 0.0f)) {
        ++degenerate;
        continue;
      }
      int mat = face < shape.mesh.material_ids.size() ? shape.mesh.material_ids[face] : -1;
      if (mat < 0 || size_t(mat) >= out.materials.size()) {
        if (default_id < 0) {
          out.materials.push_back(Material{"default"});
          default_id = int(out.materials.size() - 1);
        }
        mat = default_id;
      }
      bool has_n = idx[f].normal_index >= 0 && idx[f + 1].normal_index >= 0 && idx[f + 2].normal_index >= 0;
      any_normals |= has_n;
      mesh.indices.push_back(tri);
      normal_idx.push_back(has_n ? uvec3(uint32_t(idx[f].normal_index), uint32_t(idx[f + 1].normal_index),
                                         uint32_t(idx[f + 2].normal_index))
                                 : uvec3(0));
      mesh.materials.push_back(uint32_t(mat));
    }
  }
  if (any_normals) mesh.normal_indices = std::move(normal_idx);
  if (degenerate > 0)
    out.warnings.push_back(path + ": " + std::to_string(degenerate) + " degenerate (zero-area) triangle" +
                           (degenerate == 1 ? "" : "s") + " dropped");
  if (mesh.indices.empty()) return Error{path + ": no triangles with non-zero area"};
  return out;
}

void append_obj(Scene& scene, ObjData obj, int override_material) {
  uint32_t base = uint32_t(scene.materials.size());
  if (override_material >= 0) {
    for (uint32_t& m : obj.mesh.materials) m = uint32_t(override_material);
  } else {
    for (Material& m : obj.materials) scene.materials.push_back(std::move(m));
    for (uint32_t& m : obj.mesh.materials) m += base;
  }
  if (obj.mesh.materials.size() < obj.mesh.indices.size()) {
    // Generated meshes carry no materials: the caller passed an override.
    obj.mesh.materials.resize(obj.mesh.indices.size(), uint32_t(std::max(override_material, 0)));
  }
  for (std::string& w : obj.warnings) scene.warnings.push_back(std::move(w));
  scene.meshes.push_back(std::move(obj.mesh));
}

}  // namespace pt
