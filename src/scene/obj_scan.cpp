#include "scene/obj_scan.h"

#include <unordered_map>

#include "scene/load_internal.h"

namespace pt {

namespace {

/// Checks one face corner "v", "v/vt", "v//vn" or "v/vt/vn" against the element counts defined so far.
std::string check_corner(std::string_view corner, const size_t counts[3]) {
  static const char* const kWhat[3] = {"vertex", "texture coordinate", "normal"};
  std::string_view slots[3];
  size_t n = 0;
  for (size_t start = 0;;) {
    size_t slash = corner.find('/', start);
    if (n == 3) return "malformed face corner '" + std::string(corner) + "' (expected v, v/vt, v//vn or v/vt/vn)";
    slots[n++] = slash == std::string_view::npos ? corner.substr(start) : corner.substr(start, slash - start);
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  // "v/" and "v/vt/" and "/vt" are malformed; "v//vn" leaves only the texture slot empty.
  bool shape_ok = !slots[0].empty() && (n < 2 || !slots[1].empty() || n == 3) && (n < 3 || !slots[2].empty());
  if (!shape_ok) return "malformed face corner '" + std::string(corner) + "' (expected v, v/vt, v//vn or v/vt/vn)";
  for (size_t k = 0; k < n; ++k) {
    if (slots[k].empty()) continue;
    long long i = 0;
    if (!parse_integer(slots[k], i))
      return std::string("face ") + kWhat[k] + " index '" + std::string(slots[k]) + "' is not an integer";
    if (i == 0) return std::string("face ") + kWhat[k] + " index 0 (OBJ indices start at 1)";
    long long defined = (long long)counts[k];
    if (i > defined || -i > defined)
      return std::string("face ") + kWhat[k] + " index " + std::to_string(i) + " out of range (" +
             std::to_string(defined) + " defined so far)";
  }
  return {};
}

}  // namespace

Result<ObjScan> scan_obj(std::string_view text, const std::string& path) {
  ObjScan scan;
  std::string error;
  int current_material = -1;
  std::unordered_map<std::string, int> material_ids;
  for_each_line(text, [&](int line_no, std::string_view raw) {
    auto fail = [&](const std::string& why) {
      error = located(path, line_no) + why;
      return false;
    };
    if (raw.find('\0') != std::string_view::npos) return fail("binary data in a text file");
    std::string_view line = strip_comment(raw);
    if (line.empty()) return true;
    if (comment_start(raw) != std::string_view::npos) scan.has_inline_comments = true;
    std::string_view kw_rest[2];
    split_words(line, kw_rest, 2);
    std::string_view kw = kw_rest[0], rest = kw_rest[1];
    if (kw == "v" || kw == "vn" || kw == "vt") {
      std::string_view parts[8];
      size_t n = split_words(rest, parts, 8);
      size_t need = kw == "vt" ? 1 : 3;
      if (n < need)
        return fail("'" + std::string(kw) + "' needs " + std::to_string(need) + " numbers, found " +
                    std::to_string(n));
      for (size_t k = 0; k < n; ++k) {
        float v;
        if (!parse_finite_float(parts[k], v))
          return fail("'" + std::string(kw) + "': '" + std::string(parts[k]) + "' is not a finite number");
      }
      ++(kw == "v" ? scan.positions : kw == "vt" ? scan.texcoords : scan.normals);
    } else if (kw == "f") {
      const size_t counts[3] = {scan.positions, scan.texcoords, scan.normals};
      uint32_t corners = 0;
      for (size_t i = 0; i < rest.size();) {
        while (i < rest.size() && (rest[i] == ' ' || rest[i] == '\t')) ++i;
        if (i >= rest.size()) break;
        size_t start = i;
        while (i < rest.size() && rest[i] != ' ' && rest[i] != '\t') ++i;
        if (std::string err = check_corner(rest.substr(start, i - start), counts); !err.empty()) return fail(err);
        ++corners;
      }
      if (corners < 3) return fail("a face needs at least 3 vertices, found " + std::to_string(corners));
      if (corners > kMaxFaceCorners)
        return fail("a face with " + std::to_string(corners) + " vertices (at most " +
                    std::to_string(kMaxFaceCorners) + " are supported)");
      scan.faces.push_back({line_no, corners, current_material});
    } else if (kw == "usemtl") {
      current_material = -1;
      if (rest.empty()) return true;
      auto [it, added] = material_ids.try_emplace(std::string(rest), int(scan.materials.size()));
      if (added) scan.materials.push_back({it->first, line_no});
      current_material = it->second;
    } else if (kw == "mtllib") {
      std::string_view files[16];
      size_t n = split_words(rest, files, 16);
      for (size_t k = 0; k < n; ++k) scan.libraries.push_back({std::string(files[k]), line_no});
    }
    return true;
  });
  if (!error.empty()) return Error{error};
  return scan;
}

}  // namespace pt
