#pragma once
/// Writes a scene as a version-1 JSON scene (README schema) that loads back to the same scene: the viewer's "save
/// scene". Meshes are named by their OBJ file (relative to the JSON where possible) with their transform while
/// the file still describes them; a mesh that was edited (a moved triangle light), generated, or whose file
/// materials were edited is written next to the JSON as NAME.meshN.obj with its own .mtl. Every file is written
/// atomically (core/atomic_file), the JSON last.
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"

namespace pt {

/// `loaded_materials`: the materials as loaded, to tell whether a mesh's MTL materials were edited since.
std::optional<Error> save_scene_json(const Scene& scene, const std::vector<Material>& loaded_materials,
                                     const std::string& path);

}  // namespace pt
