#pragma once
/// The validation pass over OBJ text that runs before tinyobjloader: tinyobjloader reads "v 1 abc" as zeros,
/// skips out-of-range faces and reports no line for most problems, so every check whose failure must name a line
/// happens here. The pass also records what tinyobjloader does not keep: the line of each face (for warnings), the
/// material of each face, and the mtllib statements with their lines.
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace pt {

/// One `f` statement.
struct ObjFace {
  int line = 0;
  uint32_t corners = 0;  ///< 3 for a triangle, 4 for a quad, ...
  int material = -1;     ///< index into ObjScan::materials (the `usemtl` in force), or -1 for none
};

/// A name given to `usemtl`, with the line of its first use.
struct ObjMaterialUse {
  std::string name;
  int line = 0;
};

/// A library named by `mtllib`, with the line that names it.
struct ObjLibraryRef {
  std::string file;
  int line = 0;
};

struct ObjScan {
  size_t positions = 0, texcoords = 0, normals = 0;
  std::vector<ObjFace> faces;               ///< in file order, which is also tinyobjloader's order
  std::vector<ObjMaterialUse> materials;    ///< distinct `usemtl` names, in order of first use
  std::vector<ObjLibraryRef> libraries;
  bool has_inline_comments = false;         ///< tinyobjloader would misread them: strip before handing over
};

/// At most this many corners per face: tinyobjloader stores face sizes in an unsigned char.
inline constexpr uint32_t kMaxFaceCorners = 255;

/// Validates OBJ text and records the above. Errors, "PATH:LINE: reason": binary data; a `v` or `vn` with fewer
/// than 3 components, or a component that is not a finite number (likewise `vt` with 1-3); an `f` with fewer than
/// 3 or more than kMaxFaceCorners corners, a corner not of the form v, v/vt, v//vn or v/vt/vn, an index that is
/// not an integer, is 0, or is out of range (positive, or negative relative to the elements defined so far).
/// Everything else (comments, o, g, s, l, p, unknown statements) is accepted.
Result<ObjScan> scan_obj(std::string_view text, const std::string& path);

}  // namespace pt
