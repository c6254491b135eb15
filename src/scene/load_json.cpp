/// Scene JSON, version 1 (README "Scene JSON"). Syntax errors carry nlohmann's line; semantic errors get theirs
/// from json_locate. Extension: a mesh shape may be generated instead of read ("generate": {"kind": "torus-knot",
/// ...}), see procedural.h.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "scene/json_locate.h"
#include "scene/load.h"
#include "scene/load_internal.h"
#include "scene/procedural.h"

namespace pt {

namespace {

using json = nlohmann::json;

/// Thrown inside this file only, caught in parse_json_scene: carries the JSON path of the offending value.
struct SceneError {
  std::vector<std::string> path;
  std::string message;
};

std::string path_string(const std::vector<std::string>& path) {
  std::string s;
  for (const std::string& p : path) {
    bool index = !p.empty() && std::all_of(p.begin(), p.end(), [](char c) { return std::isdigit(uint8_t(c)); });
    if (index) s += "[" + p + "]";
    else s += (s.empty() ? "" : ".") + p;
  }
  return s;
}

/// A JSON value with the path that leads to it, for messages.
struct Node {
  const json& j;
  std::vector<std::string> path;

  [[noreturn]] void fail(const std::string& message) const { throw SceneError{path, message}; }
  Node operator[](const std::string& key) const {
    std::vector<std::string> p = path;
    p.push_back(key);
    return Node{j.at(key), p};
  }
  Node at(size_t index) const {
    std::vector<std::string> p = path;
    p.push_back(std::to_string(index));
    return Node{j.at(index), p};
  }
  bool has(const std::string& key) const { return j.is_object() && j.contains(key); }

  float number() const {
    if (!j.is_number()) fail("expected a number");
    double v = j.get<double>();
    if (!std::isfinite(v) || std::abs(v) > 3.0e38) fail("expected a finite number");
    return float(v);
  }
  vec3 vector3() const {
    if (!j.is_array() || j.size() != 3) fail("expected an array of 3 numbers");
    return {at(0).number(), at(1).number(), at(2).number()};
  }
  std::string string() const {
    if (!j.is_string()) fail("expected a string");
    return j.get<std::string>();
  }
  void expect_object() const {
    if (!j.is_object()) fail("expected an object");
  }
};

struct Context {
  std::string file;
  std::filesystem::path dir;
  Scene scene;
  std::map<std::string, uint32_t> material_ids;
  int default_material = -1;

  void warn_unknown_keys(const Node& n, std::initializer_list<const char*> known, std::string_view text) {
    for (auto it = n.j.begin(); it != n.j.end(); ++it) {
      if (std::find_if(known.begin(), known.end(), [&](const char* k) { return it.key() == k; }) != known.end())
        continue;
      std::vector<std::string> p = n.path;
      p.push_back(it.key());
      scene.warnings.push_back(file + ":" + std::to_string(json_line_of(text, p)) + ": unknown key '" +
                               path_string(p) + "' ignored");
    }
  }
  uint32_t material_ref(const Node& shape) {
    if (!shape.has("material")) {
      if (default_material < 0) {
        scene.materials.push_back(Material{"default"});
        default_material = int(scene.materials.size() - 1);
      }
      return uint32_t(default_material);
    }
    Node m = shape["material"];
    std::string name = m.string();
    auto it = material_ids.find(name);
    if (it == material_ids.end()) m.fail("unknown material '" + name + "'");
    return it->second;
  }
};

Material parse_material(const Node& n, const std::string& name) {
  n.expect_object();
  Material m;
  m.name = name;
  std::string type = n.has("type") ? n["type"].string() : "diffuse";
  if (type == "diffuse") m.type = MaterialType::diffuse;
  else if (type == "specular") m.type = MaterialType::specular;
  else if (type == "glass") m.type = MaterialType::glass;
  else n["type"].fail("unknown material type '" + type + "' (expected diffuse, specular or glass)");
  if (n.has("albedo")) {
    m.albedo = n["albedo"].vector3();
    if (min_component(m.albedo) < 0.0f) n["albedo"].fail("albedo must not be negative");
  } else if (m.type == MaterialType::glass) {
    m.albedo = vec3(1.0f);
  }
  if (n.has("ior")) {
    m.ior = n["ior"].number();
    if (!(m.ior > 0.0f)) n["ior"].fail("ior must be positive");
  }
  if (n.has("emission")) {
    m.emission = n["emission"].vector3();
    if (min_component(m.emission) < 0.0f) n["emission"].fail("emission must not be negative");
  }
  return m;
}

/// Scale, then rotate (axis-angle, degrees), then translate.
struct Transform {
  mat3 linear{1.0f};
  vec3 translate{0.0f};
};

Transform parse_transform(const Node& n) {
  n.expect_object();
  vec3 scale(1.0f);
  mat3 rotation(1.0f);
  Transform t;
  if (n.has("scale")) {
    Node s = n["scale"];
    if (s.j.is_number()) scale = vec3(s.number());
    else scale = s.vector3();
    if (scale.x == 0.0f || scale.y == 0.0f || scale.z == 0.0f) s.fail("scale must not be zero");
  }
  if (n.has("rotate")) {
    Node r = n["rotate"];
    if (!r.j.is_array() || r.j.size() != 4) r.fail("expected [axis_x, axis_y, axis_z, degrees]");
    vec3 axis(r.at(0).number(), r.at(1).number(), r.at(2).number());
    float degrees = r.at(3).number();
    float len = glm::length(axis);
    if (!(len > 0.0f) || !std::isfinite(len)) r.fail("rotation axis must be non-zero");
    axis /= len;
    float a = glm::radians(degrees), c = std::cos(a), s = std::sin(a);
    // Rodrigues' rotation formula, column-major.
    mat3 k(0, axis.z, -axis.y, -axis.z, 0, axis.x, axis.y, -axis.x, 0);
    rotation = mat3(1.0f) + s * k + (1.0f - c) * (k * k);
  }
  if (n.has("translate")) t.translate = n["translate"].vector3();
  t.linear = rotation * mat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z);
  return t;
}

void apply_transform(Mesh& mesh, const Transform& t) {
  for (vec3& p : mesh.positions) p = t.linear * p + t.translate;
  mat3 normal_matrix = glm::transpose(glm::inverse(t.linear));
  for (vec3& n : mesh.normals) n = normal_matrix * n;
  if (glm::determinant(t.linear) < 0.0f) {
    // A mirroring transform flips the winding: swap two corners to keep the front side where it was.
    for (uvec3& tri : mesh.indices) std::swap(tri.y, tri.z);
    for (uvec3& tri : mesh.normal_indices) std::swap(tri.y, tri.z);
  }
}

Mesh generate_mesh(const Node& g) {
  g.expect_object();
  std::string kind = g.has("kind") ? g["kind"].string() : "";
  if (kind != "torus-knot") g.fail("unknown generator '" + kind + "' (expected torus-knot)");
  TorusKnotParams p;
  auto get_int = [&](const char* key, int& out, int lo, int hi) {
    if (!g.has(key)) return;
    float v = g[key].number();
    if (v != std::floor(v) || v < float(lo) || v > float(hi))
      g[key].fail("expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    out = int(v);
  };
  get_int("p", p.p, 1, 64);
  get_int("q", p.q, 1, 64);
  get_int("segments", p.segments, 3, 1 << 16);
  get_int("sides", p.sides, 3, 1 << 12);
  if (g.has("radius")) p.radius = g["radius"].number();
  if (g.has("tube")) p.tube = g["tube"].number();
  if (!(p.radius > 0.0f)) g["radius"].fail("radius must be positive");
  if (!(p.tube > 0.0f)) g["tube"].fail("tube must be positive");
  if (size_t(p.segments) * size_t(p.sides) > (size_t(1) << 24)) g.fail("too many triangles");
  return make_torus_knot(p);
}

void parse_shape(Context& ctx, const Node& n, std::string_view text) {
  n.expect_object();
  if (!n.has("type")) n.fail("missing \"type\" (mesh, sphere or quad)");
  std::string type = n["type"].string();
  if (type == "sphere") {
    ctx.warn_unknown_keys(n, {"type", "center", "radius", "material"}, text);
    Sphere s;
    s.center = n.has("center") ? n["center"].vector3() : vec3(0.0f);
    if (!n.has("radius")) n.fail("sphere needs a \"radius\"");
    s.radius = n["radius"].number();
    if (!(s.radius > 0.0f)) n["radius"].fail("radius must be positive");
    s.material = ctx.material_ref(n);
    ctx.scene.spheres.push_back(s);
  } else if (type == "quad") {
    ctx.warn_unknown_keys(n, {"type", "corner", "edge1", "edge2", "material"}, text);
    for (const char* key : {"corner", "edge1", "edge2"})
      if (!n.has(key)) n.fail(std::string("quad needs \"") + key + "\"");
    Quad q{n["corner"].vector3(), n["edge1"].vector3(), n["edge2"].vector3(), ctx.material_ref(n)};
    float area = glm::length(glm::cross(q.edge1, q.edge2));
    if (!(area > 0.0f) || !std::isfinite(area)) {
      ctx.scene.warnings.push_back(ctx.file + ":" + std::to_string(json_line_of(text, n.path)) + ": " +
                                   path_string(n.path) + ": quad has zero area: skipped");
      return;
    }
    ctx.scene.quads.push_back(q);
  } else if (type == "mesh") {
    ctx.warn_unknown_keys(n, {"type", "file", "material", "transform", "generate"}, text);
    int override_material = n.has("material") ? int(ctx.material_ref(n)) : -1;
    Transform t;
    if (n.has("transform")) t = parse_transform(n["transform"]);
    ObjData obj;
    if (n.has("generate")) {
      obj.mesh = generate_mesh(n["generate"]);
      if (override_material < 0) override_material = int(ctx.material_ref(Node{json::object(), n.path}));
    } else {
      if (!n.has("file")) n.fail("mesh needs a \"file\" (or \"generate\")");
      std::string file = n["file"].string();
      std::filesystem::path p(file);
      if (p.is_relative()) p = ctx.dir / p;
      Result<ObjData> r = read_obj(p.lexically_normal().string(), override_material < 0);
      if (!r) n["file"].fail(r.error());
      obj = std::move(*r);
    }
    apply_transform(obj.mesh, t);
    append_obj(ctx.scene, std::move(obj), override_material);
  } else {
    n["type"].fail("unknown shape type '" + type + "' (expected mesh, sphere or quad)");
  }
}

void parse_camera(Context& ctx, const Node& n, std::string_view text) {
  n.expect_object();
  ctx.warn_unknown_keys(n, {"eye", "target", "up", "fov"}, text);
  Camera c;
  if (n.has("eye")) c.eye = n["eye"].vector3();
  if (n.has("target")) c.target = n["target"].vector3();
  if (n.has("up")) c.up = n["up"].vector3();
  if (n.has("fov")) c.fov_deg = n["fov"].number();
  if (!(c.fov_deg > 0.0f && c.fov_deg < 180.0f)) n["fov"].fail("fov must be between 0 and 180 degrees");
  vec3 forward = c.target - c.eye;
  if (!(glm::length(forward) > 0.0f)) n.fail("camera eye and target are the same point");
  vec3 side = glm::cross(glm::normalize(forward), c.up);
  if (!(glm::length(side) > 1e-6f * std::max(glm::length(c.up), 1e-30f)) || !(glm::length(c.up) > 0.0f))
    n.fail("camera up is zero or parallel to the view direction");
  ctx.scene.camera = c;
}

}  // namespace

Result<Scene> parse_json_scene(std::string_view text, const std::string& path) {
  json root;
  try {
    root = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    // nlohmann reports the byte offset; count lines up to it.
    size_t end = std::min<size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    int line = 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(end), '\n'));
    std::string reason = e.what();
    if (size_t colon = reason.find(": "); colon != std::string::npos) reason = reason.substr(colon + 2);
    return Error{path + ":" + std::to_string(line) + ": invalid JSON: " + reason};
  } catch (const json::out_of_range& e) {
    // "number overflow parsing '1e999'": nlohmann gives no position, so find the token in the text.
    std::string what = e.what();
    size_t q1 = what.find('\''), q2 = what.rfind('\'');
    int line = 1;
    if (q1 != std::string::npos && q2 > q1) {
      size_t at = text.find(what.substr(q1 + 1, q2 - q1 - 1));
      if (at != std::string_view::npos) line += int(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
    }
    std::string reason = what.substr(what.find(']') == std::string::npos ? 0 : what.find(']') + 2);
    return Error{path + ":" + std::to_string(line) + ": invalid JSON: " + reason};
  } catch (const std::exception& e) {
    return Error{path + ": invalid JSON: " + e.what()};
  }
  Context ctx;
  ctx.file = path;
  ctx.dir = std::filesystem::path(path).parent_path();
  ctx.scene.source = path;
  try {
    Node n{root, {}};
    n.expect_object();
    ctx.warn_unknown_keys(n, {"version", "camera", "background", "materials", "shapes"}, text);
    if (n.has("version") && !(n["version"].j.is_number() && n["version"].number() == 1.0f))
      n["version"].fail("unsupported scene version (expected 1)");
    if (n.has("camera")) parse_camera(ctx, n["camera"], text);
    if (n.has("background")) {
      vec3 bg = n["background"].vector3();
      if (min_component(bg) < 0.0f) n["background"].fail("background must not be negative");
      ctx.scene.background = bg;
    }
    if (n.has("materials")) {
      Node mats = n["materials"];
      mats.expect_object();
      for (auto it = mats.j.begin(); it != mats.j.end(); ++it) {
        ctx.scene.materials.push_back(parse_material(mats[it.key()], it.key()));
        ctx.material_ids[it.key()] = uint32_t(ctx.scene.materials.size() - 1);
      }
    }
    if (!n.has("shapes")) n.fail("missing \"shapes\"");
    Node shapes = n["shapes"];
    if (!shapes.j.is_array()) shapes.fail("expected an array of shapes");
    for (size_t i = 0; i < shapes.j.size(); ++i) parse_shape(ctx, shapes.at(i), text);
  } catch (const SceneError& e) {
    // Errors from a nested file (a mesh's OBJ) already name that file: report them with the JSON location.
    std::string where = path + ":" + std::to_string(json_line_of(text, e.path)) + ": ";
    std::string key = path_string(e.path);
    return Error{where + (key.empty() ? "" : key + ": ") + e.message};
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
  return std::move(ctx.scene);
}

}  // namespace pt
