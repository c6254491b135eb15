#include "scene/save_json.h"

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"

namespace pt {

namespace {

namespace fs = std::filesystem;
using ordered = nlohmann::ordered_json;

ordered vec(vec3 v) { return ordered::array({v.x, v.y, v.z}); }

std::string material_name(const Scene& s, uint32_t m) {
  if (m >= s.materials.size()) return "default";
  return s.materials[m].name.empty() ? "#" + std::to_string(m) : s.materials[m].name;
}

bool same(const Material& a, const Material& b) {
  return a.name == b.name && a.type == b.type && a.albedo == b.albedo && a.ior == b.ior && a.emission == b.emission;
}

/// Can the mesh be named by its file? Its geometry is the file's, and its MTL materials are as loaded.
bool file_describes(const Scene& s, const Mesh& mesh, const std::vector<Material>& loaded) {
  if (mesh.source.file.empty()) return false;
  if (!mesh.source.file_materials) return true;
  for (uint32_t m : mesh.materials)
    if (m >= s.materials.size() || m >= loaded.size() || !same(s.materials[m], loaded[m])) return false;
  return true;
}

std::string fmt(float v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", double(v));  // round-trips every float
  return b;
}

/// The mesh as OBJ text (positions relative to the mesh origin, shading normals, usemtl per run of faces) and its MTL.
void mesh_obj(const Scene& s, const Mesh& mesh, const std::string& mtl_name, std::string& obj, std::string& mtl) {
  obj = "# written by ptview's save scene\nmtllib " + mtl_name + "\n";
  for (vec3 p : mesh.positions) obj += "v " + fmt(p.x) + " " + fmt(p.y) + " " + fmt(p.z) + "\n";
  const bool normals = !mesh.normal_indices.empty() && mesh.normal_indices.size() == mesh.indices.size();
  if (normals)
    for (vec3 n : mesh.normals) obj += "vn " + fmt(n.x) + " " + fmt(n.y) + " " + fmt(n.z) + "\n";
  std::vector<bool> used(s.materials.size(), false);
  uint32_t current = UINT32_MAX;
  for (size_t t = 0; t < mesh.indices.size(); ++t) {
    uint32_t m = t < mesh.materials.size() ? mesh.materials[t] : 0u;
    if (m != current) {
      obj += "usemtl " + material_name(s, m) + "\n";
      current = m;
      if (m < used.size()) used[m] = true;
    }
    obj += "f";
    for (int k = 0; k < 3; ++k) {
      obj += " " + std::to_string(mesh.indices[t][k] + 1);
      if (normals) obj += "//" + std::to_string(mesh.normal_indices[t][k] + 1);
    }
    obj += "\n";
  }
  mtl = "# written by ptview's save scene\n";
  for (uint32_t m = 0; m < s.materials.size(); ++m) {
    if (!used[m]) continue;
    const Material& mat = s.materials[m];
    mtl += "newmtl " + material_name(s, m) + "\n";
    auto rgb = [&](const char* key, vec3 v) {
      mtl += std::string(key) + " " + fmt(v.x) + " " + fmt(v.y) + " " + fmt(v.z) + "\n";
    };
    if (mat.type == MaterialType::specular) {
      mtl += "illum 3\n";
      rgb("Ks", mat.albedo);
    } else {
      rgb("Kd", mat.albedo);
      if (mat.type == MaterialType::glass) mtl += "illum 7\nNi " + fmt(mat.ior) + "\n";
    }
    if (mat.emissive()) rgb("Ke", mat.emission);
  }
}

}  // namespace

std::optional<Error> save_scene_json(const Scene& s, const std::vector<Material>& loaded, const std::string& path) {
  const fs::path json_path(path);
  const fs::path dir = json_path.parent_path().empty() ? fs::path(".") : json_path.parent_path();
  ordered j;
  j["version"] = 1;
  if (s.camera)
    j["camera"] = {{"eye", vec(s.camera->eye)}, {"target", vec(s.camera->target)}, {"up", vec(s.camera->up)},
                   {"fov", s.camera->fov_deg}};
  if (s.background) j["background"] = vec(*s.background);
  ordered materials = ordered::object();
  for (uint32_t m = 0; m < s.materials.size(); ++m) {
    const Material& mat = s.materials[m];
    ordered o = {{"type", name_of(mat.type)}, {"albedo", vec(mat.albedo)}};
    if (info_of(mat.type).uses_ior) o["ior"] = mat.ior;
    if (mat.emissive()) o["emission"] = vec(mat.emission);
    materials[material_name(s, m)] = o;
  }
  j["materials"] = materials;
  ordered shapes = ordered::array();
  for (size_t i = 0; i < s.meshes.size(); ++i) {
    const Mesh& mesh = s.meshes[i];
    ordered shape = {{"type", "mesh"}};
    if (file_describes(s, mesh, loaded)) {
      std::error_code ec;
      fs::path rel = fs::relative(mesh.source.file, fs::absolute(dir, ec), ec);
      shape["file"] = ec || rel.empty() ? mesh.source.file : rel.generic_string();
      if (!mesh.source.file_materials && !mesh.materials.empty())
        shape["material"] = material_name(s, mesh.materials[0]);
      const MeshSource& src = mesh.source;
      shape["transform"] = {{"scale", vec(src.scale)},
                            {"rotate", {src.axis.x, src.axis.y, src.axis.z, src.degrees}},
                            {"translate", vec(src.translate)}};
    } else {
      std::string stem = json_path.stem().string() + ".mesh" + std::to_string(i);
      std::string obj, mtl;
      mesh_obj(s, mesh, stem + ".mtl", obj, mtl);
      if (auto err = write_file_atomic((dir / (stem + ".mtl")).string(), mtl)) return err;
      if (auto err = write_file_atomic((dir / (stem + ".obj")).string(), obj)) return err;
      shape["file"] = stem + ".obj";
      // The OBJ holds the positions relative to the mesh's origin (scene.h), which comes back as a translation.
      if (mesh.origin != dvec3(0.0))
        shape["transform"] = {{"translate", ordered::array({mesh.origin.x, mesh.origin.y, mesh.origin.z})}};
    }
    shapes.push_back(shape);
  }
  for (const Quad& q : s.quads)
    shapes.push_back({{"type", "quad"}, {"corner", vec(q.corner)}, {"edge1", vec(q.edge1)}, {"edge2", vec(q.edge2)},
                      {"material", material_name(s, q.material)}});
  for (const Sphere& sp : s.spheres)
    shapes.push_back({{"type", "sphere"}, {"center", vec(sp.center)}, {"radius", sp.radius},
                      {"material", material_name(s, sp.material)}});
  j["shapes"] = shapes;
  return write_file_atomic(path, j.dump(2) + "\n");
}

}  // namespace pt
