/// Scene loading entry points: dispatch on the file's extension, built-in scenes, and the helpers every loader
/// shares (file reading, material interning).
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/file_name.h"
#include "core/read_file.h"
#include "scene/builtin_assets.h"
#include "scene/load.h"
#include "scene/load_internal.h"

namespace pt {

namespace {

constexpr std::string_view kBuiltinPrefix = "builtin:";

/// Runs a loader so that nothing escapes it: the loaders catch what they expect, this catches the rest (an
/// allocation failing while finalizing a huge scene, ...) as a one-line error naming the source. Also makes sure
/// every message is one line.
template <class F>
Result<Scene> guarded(const std::string& source, F&& load) {
  try {
    Result<Scene> r = load();
    if (!r) return Error{one_line(r.error())};
    for (std::string& w : r->warnings) w = one_line(w);
    return r;
  } catch (const std::bad_alloc&) {
    return Error{source + ": out of memory"};
  } catch (const std::exception& e) {
    return Error{source + ": " + e.what()};
  }
}

Result<Scene> load_json_file(const std::string& path) {
  Result<std::string> text = read_text_file(path);
  if (!text) return Error{text.error()};
  return parse_json_scene(*text, path);
}

/// Every scene type load_scene opens: the one place that maps extensions to loaders (the viewer's drop and open
/// go through load_scene, so they get every type listed here).
struct SceneLoader {
  std::string_view extension;  ///< lower case, with its dot
  Result<Scene> (*load)(const std::string& path);
};
constexpr SceneLoader kLoaders[] = {
    {".json", &load_json_file},
    {".obj", &load_obj_scene},
    {".gltf", &load_gltf_scene},
    {".glb", &load_gltf_scene},
};

/// Whether two materials render alike: a parameter their type does not read (a glass's albedo, which an MTL
/// sets from Kd) does not tell them apart.
bool same_parameters(const Material& a, const Material& b) {
  if (a.type != b.type || a.emission != b.emission) return false;
  const MaterialTypeInfo& type = info_of(a.type);
  return (!type.uses_albedo || a.albedo == b.albedo) && (!type.uses_ior || a.ior == b.ior);
}

}  // namespace

Result<std::string> read_text_file(const std::string& path) {
  return read_whole_file(path, uint64_t(1) << 31);  // the 2 GiB cap load_internal.h documents
}

uint32_t add_material(Scene& scene, Material m) {
  std::string base = m.name;
  for (int suffix = 2;; ++suffix) {
    auto same_name = std::find_if(scene.materials.begin(), scene.materials.end(),
                                  [&](const Material& other) { return other.name == m.name; });
    if (same_name == scene.materials.end()) break;
    if (same_parameters(*same_name, m)) return uint32_t(same_name - scene.materials.begin());
    m.name = base + "#" + std::to_string(suffix);
  }
  scene.materials.push_back(std::move(m));
  return uint32_t(scene.materials.size() - 1);
}

Result<Scene> load_obj_scene(const std::string& path) {
  return guarded(path, [&]() -> Result<Scene> {
    Result<ObjData> obj = read_obj(path, true);
    if (!obj) return Error{obj.error()};
    Scene scene;
    scene.source = path;
    append_obj(scene, std::move(*obj), -1);
    std::error_code ec;
    scene.meshes.back().source = {std::filesystem::absolute(path, ec).lexically_normal().string(), true};
    return scene;
  });
}

Result<Scene> load_builtin_scene(std::string_view name) {
  std::string source = std::string(kBuiltinPrefix) + std::string(name);
  return guarded(source, [&]() -> Result<Scene> {
    for (const BuiltinAsset& a : builtin_assets()) {
      if (name != a.name) continue;
      Result<Scene> scene = parse_json_scene(a.json, source);
      if (scene) finalize_scene(*scene);
      return scene;
    }
    std::string known;
    for (const BuiltinAsset& a : builtin_assets()) known += std::string(known.empty() ? "" : ", ") + a.name;
    return Error{source + ": no such built-in scene (known: " + known + ")"};
  });
}

std::string supported_scene_extensions() {
  std::string s;
  for (size_t i = 0; i < std::size(kLoaders); ++i)
    s += std::string(i == 0 ? "" : i + 1 == std::size(kLoaders) ? " or " : ", ") + std::string(kLoaders[i].extension);
  return s;
}

Result<Scene> load_scene(const std::string& path) {
  if (path.starts_with(kBuiltinPrefix)) return load_builtin_scene(std::string_view(path).substr(kBuiltinPrefix.size()));
  return guarded(path, [&]() -> Result<Scene> {
    std::string ext = lower_extension(path);
    for (const SceneLoader& l : kLoaders) {
      if (ext != l.extension) continue;
      Result<Scene> scene = l.load(path);
      if (scene) finalize_scene(*scene);
      return scene;
    }
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return Error{path + ": cannot open: " + std::strerror(errno)};
    return Error{path + ": unsupported scene type " + (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                 " (expected " + supported_scene_extensions() + ")"};
  });
}

}  // namespace pt
