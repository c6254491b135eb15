#pragma once
/// Wavefront MTL material libraries: our own small parser (tinyobjloader cannot tell an absent Ni from Ni 1, reads
/// "Kd 0.5" as red, and reports no line numbers) and the mapping of MTL statements onto ptview's three
/// materials. The mapping is the README's "OBJ / MTL mapping" table; see material_from_mtl.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"

namespace pt {

/// The MTL statements ptview reads, as written in one newmtl block.
struct MtlRecord {
  std::string name;
  std::optional<vec3> kd;   ///< diffuse colour
  vec3 ks{0.0f};            ///< specular colour
  vec3 ke{0.0f};            ///< emitted radiance
  float ns = 0.0f;          ///< specular exponent
  std::optional<float> ni;  ///< index of refraction
  float d = 1.0f;           ///< dissolve (1 = opaque)
  float tr = 0.0f;          ///< transparency (1 - d, written by some exporters instead of d)
  std::optional<int> illum; ///< illumination model
};

/// Maps an MTL record onto a ptview material, in this order of precedence:
///   illum 3 or 5 -> specular with albedo Ks;  illum 4, 6 or 7 -> glass;
///   otherwise d < 1 or Tr > 0 -> glass;  otherwise Ks dominant over Kd (by luminance) with Ns >= 500 -> specular;
///   otherwise diffuse with albedo Kd (0.8 grey when Kd is absent).
/// Glass takes ior = Ni, or 1.5 when Ni is absent or <= 0. Every type emits Ke.
Material material_from_mtl(const MtlRecord& record);

/// The materials of one library, in file order; a repeated name keeps its first definition (with a warning).
struct MtlLibrary {
  std::vector<Material> materials;
  std::vector<std::string> warnings;  ///< "PATH:LINE: ..." each
};

/// Parses MTL text. `path` names the file in messages. Errors ("PATH:LINE: reason"): a newmtl without a name, a
/// colour that is not 1 or 3 finite non-negative numbers, a non-finite Ns/Ni/d/Tr, a non-integer illum, binary
/// data. Warnings: colours above 1 (not energy conserving), statements before the first newmtl, repeated names.
/// Statements ptview does not use (Ka, map_Kd, ...) are accepted silently.
Result<MtlLibrary> parse_mtl(std::string_view text, const std::string& path);

}  // namespace pt
