#pragma once
/// Pieces shared by the loaders (not part of the scene layer's public interface): file reading, line splitting
/// that counts lines the way tinyobjloader does, number parsing, material interning, and the OBJ hand-off from
/// load_obj.cpp to the JSON loader.
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"

namespace pt {

/// The whole file as text. Refuses what is not a regular file (a directory, a FIFO, /dev/zero) and files over
/// 2 GiB, so a bad path can never hang or exhaust memory. Errors: "PATH: cannot open: reason".
Result<std::string> read_text_file(const std::string& path);

/// "FILE:LINE: " (or "FILE: " for line <= 0): the prefix of every located message.
inline std::string located(const std::string& file, int line) {
  return line > 0 ? file + ":" + std::to_string(line) + ": " : file + ": ";
}

/// `s` with control characters written as escapes ("\\n", "\\x01"): names taken from a file (a JSON key "a\\nb", a
/// file name) must not break the one-line shape of messages.
inline std::string one_line(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    unsigned char u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) out += c;
    else if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else out += "\\x" + std::string(1, "0123456789abcdef"[u >> 4]) + "0123456789abcdef"[u & 15];
  }
  return out;
}

/// Calls fn(line_number, line) for every line of `text`, 1-based. A line ends at "\n", "\r\n" or a lone "\r",
/// exactly as tinyobjloader's safeGetline splits them, so both passes over an OBJ agree on line numbers. Stops
/// and returns false as soon as fn returns false.
template <class F>
bool for_each_line(std::string_view text, F&& fn) {
  int line_no = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string_view::npos) end = text.size();
    if (!fn(++line_no, text.substr(pos, end - pos))) return false;
    pos = end;
    if (pos < text.size() && text[pos] == '\r') {
      ++pos;
      if (pos < text.size() && text[pos] == '\n') ++pos;
    } else if (pos < text.size()) {
      ++pos;  // '\n'
    }
  }
  return true;
}

/// OBJ and MTL text with its continued lines joined: a backslash that ends a line (before "\n", "\r\n" or a lone
/// "\r") joins the next line to it, as the OBJ specification allows and Blender's importer reads it (also inside a
/// comment). The backslash and line end become one space, and the line ends taken out are put back after the joined
/// line, so every line keeps its number: an error in a joined line names its first line. Returns the text unchanged
/// (no copy) when nothing is continued, which is nearly always.
inline std::string join_continued_lines(std::string text) {
  if (text.find("\\\n") == std::string::npos && text.find("\\\r") == std::string::npos) return text;
  std::string out;
  out.reserve(text.size());
  size_t pending = 0;  // line ends taken out of the current logical line
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\\' && i + 1 < text.size() && (text[i + 1] == '\n' || text[i + 1] == '\r')) {
      out += ' ';
      i += text[i + 1] == '\r' && i + 2 < text.size() && text[i + 2] == '\n' ? 2 : 1;
      ++pending;
    } else if (c == '\n' || c == '\r') {
      out += c;
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') out += text[++i];
      out.append(pending, '\n');
      pending = 0;
    } else {
      out += c;
    }
  }
  out.append(pending, '\n');
  return out;
}

/// Where the comment of an OBJ/MTL line starts: the first '#' that begins the line or follows a space or tab
/// (so "newmtl a#1" keeps its name), or npos.
inline size_t comment_start(std::string_view line) {
  for (size_t i = line.find('#'); i != std::string_view::npos; i = line.find('#', i + 1))
    if (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t') return i;
  return std::string_view::npos;
}

/// `line` without its comment and surrounding blanks; empty for blank and comment-only lines.
inline std::string_view strip_comment(std::string_view line) {
  line = line.substr(0, comment_start(line));
  size_t first = line.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return line.substr(first, line.find_last_not_of(" \t") + 1 - first);
}

/// Splits `line` at spaces and tabs into at most `max_parts` words (the last keeps the rest of the line); returns
/// the count. A fixed array avoids a heap allocation per line when reading million-line files.
inline size_t split_words(std::string_view line, std::string_view* parts, size_t max_parts) {
  size_t n = 0, i = 0;
  while (n < max_parts) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i >= line.size()) break;
    size_t start = i;
    if (n + 1 == max_parts) {
      size_t end = line.find_last_not_of(" \t");
      parts[n++] = line.substr(start, end + 1 - start);
      break;
    }
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    parts[n++] = line.substr(start, i - start);
  }
  return n;
}

/// Parses a whole word as a finite float ("+" allowed, "nan"/"inf" and trailing characters refused). Values that
/// overflow a float are refused too: they would become infinities downstream.
inline bool parse_finite_float(std::string_view s, float& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v) || std::abs(v) > 3.4e38) return false;
  out = float(v);
  return true;
}

/// Parses a whole word as a decimal integer ("+" allowed).
inline bool parse_integer(std::string_view s, long long& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

/// Adds `m` to scene.materials and returns its index. Material names stay unique: a material with the same name
/// and the same parameters is shared (loading one OBJ twice, or the "default" grey of several files), a different
/// one with a taken name is renamed "NAME#2", "NAME#3", ...
uint32_t add_material(Scene& scene, Material m);

/// A triangle mesh read from an OBJ file with its MTL materials (or from a glTF, see GltfData). Mesh::materials index
/// into `materials`, which holds only the materials some face uses.
struct ObjData {
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<std::string> warnings;
};

/// Reads and validates an OBJ (load_obj.cpp). With `use_mtl` false the .mtl is neither read nor warned about and
/// every face gets material 0 of an empty list: the caller overrides it.
Result<ObjData> read_obj(const std::string& path, bool use_mtl);

/// A glTF scene read as one world-space mesh (load_gltf.cpp) and its perspective cameras in node order.
struct GltfData {
  ObjData geometry;
  std::vector<Camera> cameras;
};

/// Reads and validates a .gltf or .glb. With `use_materials` false every triangle gets material 0 of an empty list
/// (the caller overrides it) and no material is mapped or warned about.
Result<GltfData> read_gltf(const std::string& path, bool use_materials);

/// Appends `obj`'s mesh to `scene` with its materials interned (add_material), or with every face set to
/// `override_material` when that is >= 0; its warnings are appended too.
void append_obj(Scene& scene, ObjData obj, int override_material);

}  // namespace pt
