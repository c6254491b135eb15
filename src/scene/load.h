#pragma once
/// Scene loading. The only place that knows file formats: load_json.cpp, load_obj.cpp and load_gltf.cpp are the only
/// files that include nlohmann/json, tinyobjloader or tinygltf. Every function returns a scene or a one-line error
/// "FILE:LINE: reason" (LINE where the format has lines); none throws.
#include <string>
#include <string_view>

#include "core/result.h"
#include "scene/scene.h"

namespace pt {

/// The scene ptview opens when given no file: the Cornell box with a glass and a mirror sphere.
inline constexpr std::string_view kDefaultSceneName = "cornell-spheres";

/// Dispatches on the extension: ".json" (schema version 1, README), ".obj" (materials from its .mtl), ".gltf" or
/// ".glb" (glTF 2.0).
/// The result is finalized (see finalize_scene).
Result<Scene> load_scene(const std::string& path);

/// A scene compiled into the binary, by asset name ("cornell", "cornell-glass", ...). Finalized.
Result<Scene> load_builtin_scene(std::string_view name);

/// Parses scene JSON text. `path` names the file in messages and anchors relative mesh paths.
Result<Scene> parse_json_scene(std::string_view text, const std::string& path);

/// Loads an OBJ file (and its .mtl) as a scene with one mesh; not finalized.
Result<Scene> load_obj_scene(const std::string& path);

/// Loads a .gltf or .glb (default scene) as a scene with one mesh; the first perspective camera, if any, becomes
/// the scene's camera and all of them are listed in Scene::cameras. Not finalized.
Result<Scene> load_gltf_scene(const std::string& path);

/// The scene types load_scene opens, by lower-case extension ("(.obj, .json, .gltf, .glb)" in messages and
/// file dialogs).
std::string supported_scene_extensions();

}  // namespace pt
