#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "scene/builtin_assets.h"
#include "scene/load.h"
#include "scene/load_internal.h"

namespace pt {

namespace {

std::string lower_extension(const std::string& path) {
  size_t dot = path.find_last_of('.');
  size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

Result<std::string> read_text_file(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) return Error{path + ": cannot open: " + std::strerror(errno)};
  if (S_ISDIR(st.st_mode)) return Error{path + ": cannot open: is a directory"};
  if (!S_ISREG(st.st_mode)) return Error{path + ": cannot open: not a regular file"};
  if (st.st_size > (off_t(1) << 31)) return Error{path + ": file too large (over 2 GiB)"};
  std::ifstream f(path, std::ios::binary);
  if (!f) return Error{path + ": cannot open: " + std::strerror(errno)};
  std::string text(size_t(st.st_size), '\0');
  f.read(text.data(), std::streamsize(text.size()));
  if (!f && !f.eof()) return Error{path + ": read failed"};
  text.resize(size_t(f.gcount()));
  return text;
}

Result<Scene> load_obj_scene(const std::string& path) {
  Result<ObjData> obj = read_obj(path, true);
  if (!obj) return Error{obj.error()};
  Scene scene;
  scene.source = path;
  append_obj(scene, std::move(*obj), -1);
  return scene;
}

Result<Scene> load_builtin_scene(std::string_view name) {
  for (const BuiltinAsset& a : builtin_assets()) {
    if (name != a.name) continue;
    Result<Scene> scene = parse_json_scene(a.json, "builtin:" + std::string(name));
    if (scene) finalize_scene(*scene);
    return scene;
  }
  std::string known;
  for (const BuiltinAsset& a : builtin_assets()) known += std::string(known.empty() ? "" : ", ") + a.name;
  return Error{"builtin:" + std::string(name) + ": no such built-in scene (known: " + known + ")"};
}

Result<Scene> load_scene(const std::string& path) {
  if (path.rfind("builtin:", 0) == 0) return load_builtin_scene(std::string_view(path).substr(8));
  std::string ext = lower_extension(path);
  Result<Scene> scene = Error{""};
  if (ext == ".json") {
    Result<std::string> text = read_text_file(path);
    if (!text) return Error{text.error()};
    scene = parse_json_scene(*text, path);
  } else if (ext == ".obj") {
    scene = load_obj_scene(path);
  } else {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return Error{path + ": cannot open: " + std::strerror(errno)};
    return Error{path + ": unsupported scene type '" + ext + "' (expected .obj or .json)"};
  }
  if (scene) finalize_scene(*scene);
  return scene;
}

}  // namespace pt
