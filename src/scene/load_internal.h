#pragma once
/// Pieces shared by the loaders (not part of the scene layer's public interface).
#include <string>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"

namespace pt {

/// The whole file as text. Refuses what is not a regular file (a directory, a FIFO, /dev/zero) and files over
/// 2 GiB, so a bad path can never hang or exhaust memory. Errors: "PATH: reason".
Result<std::string> read_text_file(const std::string& path);

/// A triangle mesh read from an OBJ file with its MTL materials. Mesh::materials index into `materials`.
struct ObjData {
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<std::string> warnings;
};

/// Reads and validates an OBJ. With `use_mtl` false the .mtl is neither needed nor warned about.
Result<ObjData> read_obj(const std::string& path, bool use_mtl);

/// Appends `obj`'s materials to `scene` and its mesh (material indices remapped, or all set to
/// `override_material` when >= 0).
void append_obj(Scene& scene, ObjData obj, int override_material);

}  // namespace pt
