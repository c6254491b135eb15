#include "scene/mtl.h"

#include <set>

#include "scene/load_internal.h"

namespace pt {

Material material_from_mtl(const MtlRecord& r) {
  Material m;
  m.name = r.name;
  m.albedo = r.kd.value_or(vec3(0.8f));
  m.emission = r.ke;
  int illum = r.illum.value_or(-1);
  bool mirror_model = illum == 3 || illum == 5;
  bool glass_model = illum == 4 || illum == 6 || illum == 7;
  bool transparent = r.d < 1.0f || r.tr > 0.0f;
  bool shiny = luminance(r.ks) > luminance(m.albedo) && r.ns >= 500.0f;
  if (mirror_model || (!glass_model && !transparent && shiny)) {
    m.type = MaterialType::specular;
    m.albedo = r.ks;
  } else if (glass_model || transparent) {
    m.type = MaterialType::glass;
    m.ior = r.ni && *r.ni > 0.0f ? *r.ni : 1.5f;
  }
  return m;
}

namespace {

/// One MTL statement's arguments and where it is, for located messages.
struct Statement {
  std::string_view keyword;
  std::string_view args[5];
  size_t count = 0;  ///< number of arguments
  int line = 0;
};

class MtlParser {
 public:
  explicit MtlParser(const std::string& path) : path_(path) {}

  /// Returns an error message, or an empty string when the statement was fine.
  std::string statement(const Statement& s) {
    if (s.keyword == "newmtl") return begin(s);
    static const std::set<std::string_view> kUsed = {"Kd", "Ks", "Ke", "Ns", "Ni", "d", "Tr", "illum"};
    if (!kUsed.count(s.keyword)) return {};  // Ka, Tf, map_*, bump, Pr, ...: not ours
    if (!current_) {
      warn(s.line, "'" + std::string(s.keyword) + "' before any newmtl ignored");
      return {};
    }
    MtlRecord& r = *current_;
    if (s.keyword == "Kd" || s.keyword == "Ks" || s.keyword == "Ke") {
      if (s.count > 0 && (s.args[0] == "spectral" || s.args[0] == "xyz")) {
        warn(s.line, "'" + std::string(s.keyword) + " " + std::string(s.args[0]) + "' is not supported: ignored");
        return {};
      }
      vec3 c;
      if (std::string err = colour(s, c); !err.empty()) return err;
      if (s.keyword == "Kd") {
        r.kd = c;
        kd_line_ = s.line;
      } else if (s.keyword == "Ks") {
        r.ks = c;
        ks_line_ = s.line;
      } else {
        r.ke = c;
      }
      return {};
    }
    if (s.keyword == "illum") {
      long long v = 0;
      if (s.count < 1 || !parse_integer(s.args[0], v) || v < 0 || v > 10)
        return located(path_, s.line) + "illum: expected an integer from 0 to 10";
      r.illum = int(v);
      return {};
    }
    // Ns, Ni, d, Tr: one number ("d -halo 0.5" is the spec's only option).
    size_t at = s.keyword == "d" && s.count > 1 && s.args[0] == "-halo" ? 1 : 0;
    float v = 0.0f;
    if (s.count <= at || !parse_finite_float(s.args[at], v))
      return located(path_, s.line) + std::string(s.keyword) + ": expected a finite number";
    if (s.keyword == "Ns") r.ns = v;
    else if (s.keyword == "Ni") r.ni = v;
    else if (s.keyword == "d") r.d = std::clamp(v, 0.0f, 1.0f);
    else r.tr = std::clamp(v, 0.0f, 1.0f);
    return {};
  }

  MtlLibrary finish() {
    close();
    return std::move(library_);
  }

 private:
  std::string begin(const Statement& s) {
    close();
    if (s.count == 0) return located(path_, s.line) + "newmtl without a name";
    current_ = MtlRecord{};
    current_->name = std::string(s.args[0]);
    kd_line_ = ks_line_ = 0;
    newmtl_line_ = s.line;
    return {};
  }
  /// 1 or 3 finite, non-negative numbers; one number means grey.
  std::string colour(const Statement& s, vec3& c) const {
    std::string bad = located(path_, s.line) + std::string(s.keyword) + ": expected 1 or 3 finite numbers";
    if (s.count != 1 && s.count != 3) return bad;
    for (size_t k = 0; k < s.count; ++k)
      if (!parse_finite_float(s.args[k], c[int(k)])) return bad;
    if (s.count == 1) c = vec3(c.x);
    if (min_component(c) < 0.0f) return located(path_, s.line) + std::string(s.keyword) + " must not be negative";
    return {};
  }
  void close() {
    if (!current_) return;
    Material m = material_from_mtl(*current_);
    int albedo_line = m.type == MaterialType::specular ? ks_line_ : kd_line_;
    if (m.type != MaterialType::glass && max_component(m.albedo) > 1.0f)
      warn(albedo_line, "material '" + m.name + "': reflectance above 1 does not conserve energy");
    if (!names_.insert(m.name).second)
      warn(newmtl_line_, "material '" + m.name + "' defined again: the first definition is used");
    else
      library_.materials.push_back(std::move(m));
    current_.reset();
  }
  void warn(int line, const std::string& what) { library_.warnings.push_back(located(path_, line) + what); }

  const std::string& path_;
  MtlLibrary library_;
  std::optional<MtlRecord> current_;
  std::set<std::string> names_;
  int newmtl_line_ = 0, kd_line_ = 0, ks_line_ = 0;
};

}  // namespace

Result<MtlLibrary> parse_mtl(std::string_view text, const std::string& path) {
  MtlParser parser(path);
  std::string error;
  for_each_line(text, [&](int line_no, std::string_view line) {
    if (line.find('\0') != std::string_view::npos) {
      error = located(path, line_no) + "binary data in a text file";
      return false;
    }
    line = strip_comment(line);
    if (line.empty()) return true;
    Statement s;
    s.line = line_no;
    std::string_view parts[6];
    size_t n = split_words(line, parts, 2);
    s.keyword = parts[0];
    if (n > 1 && s.keyword == "newmtl") {
      s.args[0] = parts[1];  // the rest of the line: names may contain spaces
      s.count = 1;
    } else if (n > 1) {
      s.count = split_words(parts[1], s.args, 5);
    }
    error = parser.statement(s);
    return error.empty();
  });
  if (!error.empty()) return Error{error};
  return parser.finish();
}

}  // namespace pt
