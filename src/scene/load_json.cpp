/// Scene JSON, version 1 (README "Scene JSON"). Syntax errors carry nlohmann's line; semantic errors get theirs
/// from json_locate, so every error reads "FILE:LINE: key.path: reason" and every warning likewise.
///
/// Extension (ours): a mesh shape may be generated instead of read from a file,
///   {"type": "mesh", "generate": {"kind": "torus-knot", "p": 2, "q": 3, "segments": N, "sides": M,
///                                 "radius": R, "tube": r}, "material": ..., "transform": ...}
/// built by make_torus_knot (procedural.h); the transform applies as for files. p and q must be coprime integers in
/// [1, 64] (else the tube retraces itself); segments * sides is capped at 2^24.
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numeric>
#include <unordered_map>

#include "core/file_name.h"
#include "scene/json_locate.h"
#include "scene/load.h"
#include "scene/load_internal.h"
#include "scene/procedural.h"
#include "scene/transform.h"

namespace pt {

namespace {

// ordered_json keeps the file's order of materials (the viewer lists them so).
using json = nlohmann::ordered_json;
using JsonPath = std::vector<std::string>;

/// Thrown inside this file only, and always caught in parse_json_scene: the path of the offending value, which
/// becomes a line there.
struct JsonError {
  JsonPath path;
  std::string message;
};

/// "shapes[2].corner" for {"shapes", "2", "corner"}.
std::string path_string(const JsonPath& path) {
  std::string s;
  for (const std::string& p : path) {
    bool index = !p.empty() && std::all_of(p.begin(), p.end(), [](char c) { return c >= '0' && c <= '9'; });
    s += index ? "[" + p + "]" : (s.empty() ? "" : ".") + p;
  }
  return s;
}

bool all_numbers(const json& j) {
  return std::all_of(j.begin(), j.end(), [](const json& e) { return e.is_number(); });
}

/// A JSON value and the path that leads to it, with typed accessors that fail with a located message.
class Node {
 public:
  Node(const json& value, JsonPath path) : j_(value), path_(std::move(path)) {}

  const json& value() const { return j_; }
  const JsonPath& path() const { return path_; }
  [[noreturn]] void fail(const std::string& message) const { throw JsonError{path_, message}; }

  /// The member `key`, if this is an object that has it.
  std::optional<Node> get(const std::string& key) const {
    if (!j_.is_object()) return std::nullopt;
    auto it = j_.find(key);
    if (it == j_.end()) return std::nullopt;
    return child(*it, key);
  }
  Node require(const std::string& key, const std::string& what) const {
    std::optional<Node> n = get(key);
    if (!n) fail("missing \"" + key + "\" (" + what + ")");
    return *n;
  }
  Node element(size_t index) const { return child(j_.at(index), std::to_string(index)); }

  void expect_object() const {
    if (!j_.is_object()) fail("expected an object");
  }
  float number() const {
    if (!j_.is_number()) fail("expected a number");
    double v = j_.get<double>();
    if (!std::isfinite(v) || std::abs(v) > 3.4e38) fail("expected a finite number");
    return float(v);
  }
  int integer(int lo, int hi) const {
    float v = number();
    if (v != std::floor(v) || v < float(lo) || v > float(hi))
      fail("expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    return int(v);
  }
  vec3 vector3() const {
    if (!j_.is_array() || j_.size() != 3 || !all_numbers(j_))
      fail("expected an array of 3 numbers");
    return {element(0).number(), element(1).number(), element(2).number()};
  }
  std::string string() const {
    if (!j_.is_string()) fail("expected a string");
    return j_.get<std::string>();
  }

 private:
  Node child(const json& value, const std::string& key) const {
    JsonPath p = path_;
    p.push_back(key);
    return Node(value, std::move(p));
  }

  const json& j_;
  JsonPath path_;
};

/// State of one parse: the scene being built and what messages need to locate themselves.
class SceneBuilder {
 public:
  SceneBuilder(std::string_view text, const std::string& file) : text_(text), file_(file) {
    scene.source = file;
    dir_ = std::filesystem::path(file).parent_path();
  }

  Scene scene;

  /// Locating a warning scans the text, so a file with a typo repeated in every one of a million shapes would take
  /// quadratic time: after kMaxWarnings, the rest are only counted (see finish).
  void warn(const JsonPath& path, const std::string& message) {
    if (located_warnings_ >= kMaxWarnings) {
      ++unshown_warnings_;
      return;
    }
    ++located_warnings_;
    std::string key = path_string(path);
    scene.warnings.push_back(located(file_, json_line_of(text_, path)) + (key.empty() ? "" : key + ": ") + message);
  }
  Scene finish() {
    if (unshown_warnings_ > 0)
      scene.warnings.push_back(file_ + ": " + std::to_string(unshown_warnings_) + " more warnings not shown");
    return std::move(scene);
  }
  /// Unknown keys are likely typos: one warning each, naming the key.
  void check_keys(const Node& n, std::initializer_list<std::string_view> known) {
    for (auto it = n.value().begin(); it != n.value().end(); ++it)
      if (std::find(known.begin(), known.end(), it.key()) == known.end()) {
        JsonPath p = n.path();
        p.push_back(it.key());
        warn(p, "unknown key ignored");
      }
  }

  void parse_root(const Node& root) {
    if (!root.value().is_object()) root.fail("expected a JSON object at the top level");
    check_keys(root, {"version", "camera", "background", "materials", "shapes"});
    if (auto v = root.get("version"); v && !(v->value().is_number() && v->value().get<double>() == 1.0))
      v->fail("unsupported scene version " + v->value().dump() + " (expected 1)");
    if (auto c = root.get("camera")) parse_camera(*c);
    if (auto b = root.get("background")) {
      vec3 bg = b->vector3();
      if (min_component(bg) < 0.0f) b->fail("background radiance must not be negative");
      scene.background = bg;
    }
    if (auto mats = root.get("materials")) {
      mats->expect_object();
      for (auto it = mats->value().begin(); it != mats->value().end(); ++it) {
        Node m = *mats->get(it.key());
        material_ids_[it.key()] = add_material(scene, parse_material(m, it.key()));
      }
    }
    Node shapes = root.require("shapes", "the list of shapes, may be empty");
    if (!shapes.value().is_array()) shapes.fail("expected an array of shapes");
    for (size_t i = 0; i < shapes.value().size(); ++i) parse_shape(shapes.element(i));
  }

 private:
  void parse_camera(const Node& n) {
    n.expect_object();
    check_keys(n, {"eye", "target", "up", "fov"});
    Camera c;
    auto eye = n.get("eye"), target = n.get("target"), up = n.get("up"), fov = n.get("fov");
    if (eye) c.eye = eye->vector3();
    if (target) c.target = target->vector3();
    if (up) c.up = up->vector3();
    if (fov) c.fov_deg = fov->number();
    if (!(c.fov_deg > 0.0f && c.fov_deg < 180.0f))
      (fov ? *fov : n).fail("fov must be between 0 and 180 degrees (exclusive)");
    // In double, so that a camera 1e-20 or 1e20 from its target is not taken for a degenerate one.
    const dvec3 forward = dvec3(c.target) - dvec3(c.eye), dup(c.up);
    const Node& where = target ? *target : eye ? *eye : n;
    if (!(glm::length(forward) > 0.0)) where.fail("camera eye and target are the same point");
    if (!(glm::length(dup) > 0.0)) (up ? *up : n).fail("camera up must not be zero");
    if (!(glm::length(glm::cross(glm::normalize(forward), glm::normalize(dup))) > 1e-6))
      (up ? *up : where).fail("camera up is parallel to the view direction");
    scene.camera = c;
    json_camera_ = true;
  }

  Material parse_material(const Node& n, const std::string& name) {
    n.expect_object();
    check_keys(n, {"type", "albedo", "ior", "emission"});
    Material m;
    m.name = name;
    if (auto type = n.get("type")) {
      std::string t = type->string();
      std::optional<MaterialType> v = value_of<MaterialType>(kMaterialTypeNames, t);
      if (!v)
        type->fail("unknown material type '" + t + "' (expected " + names_list<MaterialType>(kMaterialTypeNames) + ")");
      m.type = *v;
    }
    if (auto albedo = n.get("albedo")) {
      m.albedo = albedo->vector3();
      if (min_component(m.albedo) < 0.0f) albedo->fail("albedo must not be negative");
      if (max_component(m.albedo) > 1.0f) warn(albedo->path(), "albedo above 1 does not conserve energy");
    }
    if (auto ior = n.get("ior")) {
      m.ior = ior->number();
      if (!(m.ior > 0.0f)) ior->fail("ior must be positive");
    }
    if (auto emission = n.get("emission")) {
      m.emission = emission->vector3();
      if (min_component(m.emission) < 0.0f) emission->fail("emission must not be negative");
    }
    return m;
  }

  /// The material a shape names, or the shared default grey when it names none.
  uint32_t material_of(const Node& shape) {
    auto ref = shape.get("material");
    if (!ref) return add_material(scene, Material{"default"});
    std::string name = ref->string();
    auto it = material_ids_.find(name);
    if (it == material_ids_.end()) ref->fail("unknown material '" + name + "'");
    return it->second;
  }

  void parse_shape(const Node& n) {
    n.expect_object();
    std::string type = n.require("type", "mesh, sphere or quad").string();
    if (type == "sphere") {
      check_keys(n, {"type", "center", "radius", "material"});
      Sphere s;
      if (auto center = n.get("center")) s.center = center->vector3();
      Node radius = n.require("radius", "a positive number");
      s.radius = radius.number();
      if (!(s.radius > 0.0f)) radius.fail("radius must be positive");
      s.material = material_of(n);
      scene.spheres.push_back(s);
    } else if (type == "quad") {
      check_keys(n, {"type", "corner", "edge1", "edge2", "material"});
      Quad q;
      q.corner = n.require("corner", "a point").vector3();
      q.edge1 = n.require("edge1", "a vector").vector3();
      q.edge2 = n.require("edge2", "a vector").vector3();
      // In double: float squares of the cross product overflow for quads 1e10 across and vanish below 1e-10.
      const double area = glm::length(glm::cross(dvec3(q.edge1), dvec3(q.edge2)));
      if (!is_finite(q.corner + q.edge1 + q.edge2)) n.fail("quad too large (its far corner is beyond float's range)");
      if (area > 0.0) {
        q.material = material_of(n);
        scene.quads.push_back(q);
      } else {
        if (n.get("material")) material_of(n);  // a dangling reference is an error all the same
        warn(n.path(), "quad has zero area: skipped");
      }
    } else if (type == "mesh") {
      parse_mesh(n);
    } else {
      n.require("type", "").fail("unknown shape type '" + type + "' (expected mesh, sphere or quad)");
    }
  }

  void parse_mesh(const Node& n) {
    check_keys(n, {"type", "file", "generate", "material", "transform", "camera"});
    auto file = n.get("file"), generate = n.get("generate"), transform = n.get("transform");
    if (file && generate) generate->fail("a mesh has either \"file\" or \"generate\", not both");
    if (!file && !generate) n.fail("missing \"file\" (an .obj, .gltf or .glb path; or \"generate\")");
    int override_material = n.get("material") ? int(material_of(n)) : -1;
    Transform t;
    MeshSource source;
    if (transform) t = parse_transform(*transform, source);
    ObjData obj;
    bool gltf = false;
    if (generate) {
      if (override_material < 0) override_material = int(add_material(scene, Material{"default"}));
      obj.mesh = generate_mesh(*generate);
    } else {
      std::filesystem::path p(file->string());
      if (p.is_relative()) p = dir_ / p;
      const std::string ext = lower_extension(p);
      gltf = ext == ".gltf" || ext == ".glb";
      if (gltf) {
        Result<GltfData> r = read_gltf(p.lexically_normal().string(), override_material < 0);
        if (!r) file->fail(r.error());
        obj = std::move(r->geometry);
        add_gltf_cameras(n, r->cameras, t);
      } else {
        // Any other extension is read as OBJ too (an OBJ saved as .txt); when that fails, the error says so, since
        // "no faces" alone would puzzle whoever gave a .ply or an .fbx.
        Result<ObjData> r = read_obj(p.lexically_normal().string(), override_material < 0);
        if (!r)
          file->fail(r.error() +
                     (ext == ".obj" ? "" : " (read as OBJ: a mesh file is an .obj, .gltf or .glb, by its extension)"));
        obj = std::move(*r);
      }
      std::error_code ec;
      source.file = std::filesystem::absolute(p, ec).lexically_normal().string();
      source.file_materials = override_material < 0;
      obj.mesh.source = source;
    }
    if (auto camera = n.get("camera"); camera && !gltf) camera->fail("\"camera\" picks a camera of a .gltf/.glb file");
    apply_transform(obj.mesh, t);
    append_obj(scene, std::move(obj), override_material);
  }

  /// A glTF shape's cameras, moved by the shape's transform, join Scene::cameras (for --camera N); "camera": N on
  /// the shape makes its camera N the scene's camera, unless the scene JSON has a "camera" of its own.
  void add_gltf_cameras(const Node& shape, const std::vector<Camera>& cameras, const Transform& t) {
    size_t first = scene.cameras.size();
    for (Camera c : cameras) {
      c.eye = t.linear * c.eye + t.translation;
      c.target = t.linear * c.target + t.translation;
      c.up = t.linear * c.up;
      scene.cameras.push_back(c);
    }
    auto pick = shape.get("camera");
    if (!pick) return;
    int index = pick->integer(0, 1 << 20);
    if (size_t(index) >= cameras.size())
      pick->fail("camera " + std::to_string(index) + " out of range (the file has " + std::to_string(cameras.size()) +
                 " perspective cameras)");
    if (json_camera_) pick->fail("the scene already has a \"camera\"");
    scene.camera = scene.cameras[first + size_t(index)];
  }

  Transform parse_transform(const Node& n, MeshSource& source) {
    n.expect_object();
    check_keys(n, {"scale", "rotate", "translate"});
    vec3 scale(1.0f), axis(0.0f, 1.0f, 0.0f), translate(0.0f);
    float degrees = 0.0f;
    if (auto s = n.get("scale")) {
      scale = s->value().is_number() ? vec3(s->number()) : s->vector3();
      if (min_component(glm::abs(scale)) == 0.0f) s->fail("scale must not be zero");
    }
    if (auto r = n.get("rotate")) {
      const json& v = r->value();
      if (!v.is_array() || v.size() != 4 || !all_numbers(v))
        r->fail("expected an array of 4 numbers [axis_x, axis_y, axis_z, degrees]");
      axis = vec3(r->element(0).number(), r->element(1).number(), r->element(2).number());
      degrees = r->element(3).number();
      float len = glm::length(axis);
      if (!(len > 0.0f) || !std::isfinite(len)) r->fail("rotation axis must not be zero");
    }
    if (auto tr = n.get("translate")) translate = tr->vector3();
    source.scale = scale, source.axis = axis, source.degrees = degrees, source.translate = translate;
    return make_transform(scale, axis, degrees, translate);
  }

  Mesh generate_mesh(const Node& g) {
    g.expect_object();
    check_keys(g, {"kind", "p", "q", "segments", "sides", "radius", "tube"});
    Node kind = g.require("kind", "torus-knot");
    if (kind.string() != "torus-knot") kind.fail("unknown generator '" + kind.string() + "' (expected torus-knot)");
    TorusKnotParams k;
    if (auto v = g.get("p")) k.p = v->integer(1, 64);
    if (auto v = g.get("q")) k.q = v->integer(1, 64);
    if (std::gcd(k.p, k.q) != 1) g.fail("p and q must be coprime (else the tube retraces itself)");
    if (auto v = g.get("segments")) k.segments = v->integer(3, 1 << 20);
    if (auto v = g.get("sides")) k.sides = v->integer(3, 1 << 12);
    if (size_t(k.segments) * size_t(k.sides) > (size_t(1) << 24)) g.fail("segments * sides must be at most 2^24");
    for (auto [key, value] : {std::pair{"radius", &k.radius}, std::pair{"tube", &k.tube}})
      if (auto v = g.get(key)) {
        *value = v->number();
        if (!(*value > 0.0f)) v->fail(std::string(key) + " must be positive");
      }
    return make_torus_knot(k);
  }

  static constexpr size_t kMaxWarnings = 100;
  std::string_view text_;
  const std::string& file_;
  size_t located_warnings_ = 0, unshown_warnings_ = 0;
  std::filesystem::path dir_;
  std::unordered_map<std::string, uint32_t> material_ids_;
  bool json_camera_ = false;
};

/// "FILE:LINE: invalid JSON (column C): reason" from nlohmann's parse_error, whose message reads
/// "[json.exception.parse_error.101] parse error at line L, column C: reason".
std::string syntax_error(const json::parse_error& e, std::string_view text, const std::string& path) {
  std::string what = e.what();
  int line = 0, column = 0;
  std::string reason = what;
  if (size_t at = what.find(" at line "); at != std::string::npos)
    std::sscanf(what.c_str() + at, " at line %d, column %d", &line, &column);
  if (size_t colon = what.find(": ", what.find(']')); colon != std::string::npos) reason = what.substr(colon + 2);
  if (line > 1 && column == 0) --line;  // the offending character is the newline that ended the line before
  if (line <= 0) {  // no position in the message: count lines up to the byte offset
    size_t end = std::min<size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    line = 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(end), '\n'));
  }
  return located(path, line) + "invalid JSON" + (column > 0 ? " (column " + std::to_string(column) + ")" : "") +
         ": " + reason;
}

/// The parse itself; parse_json_scene makes its messages one line each.
Result<Scene> parse_json_text(std::string_view text, const std::string& path) {
  try {
    if (size_t nul = text.find('\0'); nul != std::string_view::npos)
      return Error{located(path, 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(nul), '\n'))) +
                   "binary data in a text file"};
    json root;
    try {
      root = json::parse(text.begin(), text.end());
    } catch (const json::parse_error& e) {
      return Error{syntax_error(e, text, path)};
    } catch (const json::out_of_range& e) {
      // "number overflow parsing '1e999'": no position given, so find the literal.
      std::string what = e.what();
      size_t q1 = what.find('\''), q2 = what.rfind('\'');
      int line = q2 > q1 && q1 != std::string::npos ? json_line_of_token(text, what.substr(q1 + 1, q2 - q1 - 1)) : 0;
      return Error{located(path, line) + "invalid JSON: " + what.substr(what.find(']') + 2)};
    }
    SceneBuilder builder(text, path);
    try {
      builder.parse_root(Node(root, {}));
    } catch (const JsonError& e) {
      std::string key = path_string(e.path);
      return Error{located(path, json_line_of(text, e.path)) + (key.empty() ? "" : key + ": ") + e.message};
    }
    return builder.finish();
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  } catch (const std::exception& e) {  // nlohmann type errors we did not foresee: still one line, never a throw
    return Error{path + ": " + e.what()};
  }
}

}  // namespace

Result<Scene> parse_json_scene(std::string_view text, const std::string& path) {
  Result<Scene> r = parse_json_text(text, path);
  if (!r) return Error{one_line(r.error())};
  for (std::string& w : r->warnings) w = one_line(w);
  return r;
}

}  // namespace pt
