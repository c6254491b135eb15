/// glTF 2.0 (.gltf with .bin files or data URIs, and .glb) as one triangle mesh in world space, plus its cameras.
///
/// Material mapping (README "glTF mapping"; material_from_gltf applies it):
///   KHR_materials_transmission >= 0.5 -> glass, ior from KHR_materials_ior (1.5 by default);
///   else metallicFactor >= 0.5 and roughnessFactor <= kMirrorRoughness -> mirror tinted by the base colour;
///   else diffuse with albedo baseColorFactor (times the mean of baseColorTexture, if any);
///   emissiveFactor x KHR_materials_emissive_strength (x the mean of emissiveTexture) -> emission, so the primitive
///   is a light. Approximations (textures, a metal that is neither near-smooth nor fully diffuse, alphaMode) are
///   reported in one warning per material, naming it. Primitives without a material get diffuse 0.8 grey
///   ("default") as OBJ faces do (glTF's own default, a white rough metal, would reflect all light).
/// Geometry: triangles, strips and fans (converted); points and lines skipped with a warning naming the mesh;
/// indexed or not (u8/u16/u32), strided and interleaved views, sparse accessors (applied here: tinygltf 2.7 parses
/// them but does not resolve them), KHR_mesh_quantization's integer positions and normals; NORMAL gives shading
/// normals as OBJ vn does. The default scene's node tree
/// (matrix or TRS) places every mesh instance; a negative-determinant transform keeps the front side (two corners
/// swapped, as for mirrored JSON transforms). Skins, morph targets and animations are ignored (rest pose).
///
/// tinygltf parses the JSON / GLB container, decodes data URIs and reads external buffers through our file
/// callbacks (regular files only, as read_text_file). It checks little else, so every index and byte range is
/// validated here before use. Errors: "FILE: reason".
#include <sys/stat.h>

#include <stb_image.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/file_name.h"
#include "scene/load.h"
#include "scene/load_internal.h"

namespace pt {

using dvec4 = glm::dvec4;
using dmat4 = glm::dmat4;

namespace {

/// Roughness at or below which a metal is a mirror; above it a metal becomes diffuse. Only a near-smooth metal
/// (roughness <= kSmoothRoughness) is a mirror without comment, and only a near-fully rough one (>= kRoughRoughness)
/// diffuse without comment; in between, either is an approximation and is warned about.
constexpr double kSmoothRoughness = 0.05;
constexpr double kMirrorRoughness = 0.3;
constexpr double kRoughRoughness = 0.9;
/// Limits that keep a small hostile file from asking for gigabytes: elements of an accessor with no buffer view
/// (zeros plus sparse values), and triangles read in total over all mesh instances.
constexpr size_t kMaxZeroAccessor = size_t(1) << 22;
constexpr size_t kMaxTriangles = size_t(1) << 27;
/// Images larger than this (in pixels) are not decoded for their mean colour.
constexpr long long kMaxImagePixels = 1ll << 26;

/// Thrown inside this file only; read_gltf turns it into "FILE: message".
struct GltfError {
  std::string message;
};
[[noreturn]] void fail(std::string message) { throw GltfError{std::move(message)}; }

// --- tinygltf callbacks ----------------------------------------------------------------------------------------

bool file_exists(const std::string& path, void*) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
std::string expand_path(const std::string& path, void*) { return path; }
bool read_file_callback(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  Result<std::string> text = read_text_file(path);
  if (!text) {
    if (err) *err += text.error() + "\n";
    return false;
  }
  out->assign(text->begin(), text->end());
  return true;
}
bool write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported\n";
  return false;
}

/// sRGB-encoded 8-bit value to linear (IEC 61966-2-1).
float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

/// What the image callback learns: each image's mean linear colour, or why it has none.
struct ImageMeans {
  std::map<int, vec3> mean;
  std::map<int, std::string> failure;
};

/// tinygltf's image callback: decodes with stb_image and keeps only the mean colour (linear RGB, alpha ignored), so
/// textures cost no memory after loading. A failure is remembered, not an error: the texture is then ignored.
bool decode_image_mean(tinygltf::Image*, const int index, std::string*, std::string*, int, int,
                       const unsigned char* bytes, int size, void* user) {
  auto& means = *static_cast<ImageMeans*>(user);
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(bytes, size, &w, &h, &channels)) {
    means.failure[index] = std::string("cannot decode (") + stbi_failure_reason() + ")";
    return true;
  }
  if (w <= 0 || h <= 0 || (long long)w * h > kMaxImagePixels) {
    means.failure[index] = "too large to average";
    return true;
  }
  unsigned char* pixels = stbi_load_from_memory(bytes, size, &w, &h, &channels, 3);
  if (!pixels) {
    means.failure[index] = std::string("cannot decode (") + stbi_failure_reason() + ")";
    return true;
  }
  float lut[256];
  for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(float(i) / 255.0f);
  dvec3 sum(0.0);
  size_t n = size_t(w) * size_t(h);
  for (size_t i = 0; i < n; ++i) sum += dvec3(lut[pixels[3 * i]], lut[pixels[3 * i + 1]], lut[pixels[3 * i + 2]]);
  stbi_image_free(pixels);
  means.mean[index] = vec3(sum / double(n));
  return true;
}

// --- accessors -------------------------------------------------------------------------------------------------

/// The unsigned integer of `size` (1, 2 or 4) bytes at p, little-endian as glTF and .glb store them.
uint32_t little_endian(const unsigned char* p, size_t size) {
  if (size == 1) return *p;
  if (size == 2) return uint32_t(p[0]) | uint32_t(p[1]) << 8;
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

size_t component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

std::string name_of(const std::string& kind, size_t index, const std::string& name) {
  return kind + " " + std::to_string(index) + (name.empty() ? "" : " '" + name + "'");
}

class Reader {
 public:
  explicit Reader(const tinygltf::Model& model) : m_(model) {}

  /// The VEC3 elements of accessor `index` (POSITION, NORMAL), sparse substitutions applied: float, or the
  /// (normalized) byte and short of KHR_mesh_quantization, which gltfpack writes by default. A normalized integer
  /// maps to [0, 1] or [-1, 1] as glTF 2.0 section 3.11 says; a plain one is its value (the node's transform scales
  /// it back).
  std::vector<vec3> vec3s(int index, const std::string& what) {
    const tinygltf::Accessor& a = accessor(index, what);
    const int type = a.componentType;
    const size_t size = component_size(type);
    if (a.type != TINYGLTF_TYPE_VEC3 || size == 0 || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(what + " " + label(index) + " must be VEC3 of float (or of byte or short, KHR_mesh_quantization)");
    std::vector<vec3> out(a.count, vec3(0.0f));
    read(a, index, 3 * size, [&](size_t i, const unsigned char* p) {
      for (int k = 0; k < 3; ++k) out[i][k] = component_at(p + size_t(k) * size, type, a.normalized);
    });
    return out;
  }

  /// The SCALAR unsigned byte / short / int elements of accessor `index` (triangle indices).
  std::vector<uint32_t> indices(int index, const std::string& what) {
    const tinygltf::Accessor& a = accessor(index, what);
    size_t size = component_size(a.componentType);
    if (a.type != TINYGLTF_TYPE_SCALAR || !unsigned_type(a.componentType))
      fail(what + " " + label(index) + " must be SCALAR of unsigned byte, short or int");
    std::vector<uint32_t> out(a.count, 0u);
    read(a, index, size, [&](size_t i, const unsigned char* p) { out[i] = little_endian(p, size); });
    return out;
  }

 private:
  static bool unsigned_type(int t) {
    return t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  /// One float, byte or short component (little-endian, as glTF stores them).
  static float component_at(const unsigned char* p, int type, bool normalized) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const float v = float(int8_t(*p));
        return normalized ? std::max(v / 127.0f, -1.0f) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? float(*p) / 255.0f : float(*p);
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        const float v = float(int16_t(uint16_t(little_endian(p, 2))));
        return normalized ? std::max(v / 32767.0f, -1.0f) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        const float v = float(little_endian(p, 2));
        return normalized ? v / 65535.0f : v;
      }
      default: {
        const uint32_t bits = little_endian(p, 4);
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
      }
    }
  }
  std::string label(int index) const { return name_of("accessor", size_t(index), m_.accessors[size_t(index)].name); }

  const tinygltf::Accessor& accessor(int index, const std::string& what) const {
    if (index < 0 || size_t(index) >= m_.accessors.size())
      fail(what + " accessor " + std::to_string(index) + " out of range (" +
           std::to_string(m_.accessors.size()) + " accessors)");
    return m_.accessors[size_t(index)];
  }

  /// Start and stride of `count` elements of `size` bytes at `offset` in buffer view `view`, checked against the
  /// view's and its buffer's ends.
  const unsigned char* locate(int view, size_t offset, size_t count, size_t size, bool strided, size_t& stride,
                              const std::string& who) const {
    if (view < 0 || size_t(view) >= m_.bufferViews.size())
      fail(who + ": bufferView " + std::to_string(view) + " out of range (" + std::to_string(m_.bufferViews.size()) +
           " buffer views)");
    const tinygltf::BufferView& v = m_.bufferViews[size_t(view)];
    std::string vname = name_of("bufferView", size_t(view), v.name);
    if (v.buffer < 0 || size_t(v.buffer) >= m_.buffers.size())
      fail(vname + ": buffer " + std::to_string(v.buffer) + " out of range (" + std::to_string(m_.buffers.size()) +
           " buffers)");
    size_t have = m_.buffers[size_t(v.buffer)].data.size();
    if (v.byteOffset > have || v.byteLength > have - v.byteOffset)
      fail(vname + ": bytes " + std::to_string(v.byteOffset) + " + " + std::to_string(v.byteLength) +
           " overlap the end of buffer " + std::to_string(v.buffer) + " (" + std::to_string(have) + " bytes)");
    stride = strided && v.byteStride != 0 ? v.byteStride : size;
    if (stride < size) fail(vname + ": byteStride " + std::to_string(stride) + " is smaller than an element");
    if (count > 0) {
      bool fits = offset <= v.byteLength && size <= v.byteLength - offset &&
                  (count - 1) <= (v.byteLength - offset - size) / stride;
      if (!fits)
        fail(who + ": " + std::to_string(count) + " elements from byte " + std::to_string(offset) +
             " overlap the end of " + vname + " (" + std::to_string(v.byteLength) + " bytes)");
    }
    return m_.buffers[size_t(v.buffer)].data.data() + v.byteOffset + offset;
  }

  /// Calls put(i, bytes) for every element of `a` (element size `size`), then for every sparse substitution.
  template <class Put>
  void read(const tinygltf::Accessor& a, int index, size_t size, Put&& put) const {
    std::string who = label(index);
    if (a.bufferView >= 0) {
      size_t stride = 0;
      const unsigned char* p = locate(a.bufferView, a.byteOffset, a.count, size, true, stride, who);
      for (size_t i = 0; i < a.count; ++i) put(i, p + i * stride);
    } else if (a.count > kMaxZeroAccessor) {
      fail(who + ": " + std::to_string(a.count) + " elements without a bufferView (at most " +
           std::to_string(kMaxZeroAccessor) + ")");
    }
    if (!a.sparse.isSparse) return;
    if (a.sparse.count < 0 || size_t(a.sparse.count) > a.count)
      fail(who + ": sparse count " + std::to_string(a.sparse.count) + " exceeds the accessor's count");
    size_t n = size_t(a.sparse.count), isize = component_size(a.sparse.indices.componentType), stride = 0;
    if (!unsigned_type(a.sparse.indices.componentType))
      fail(who + ": sparse indices must be unsigned byte, short or int");
    const unsigned char* idx = locate(a.sparse.indices.bufferView, size_t(std::max(0, a.sparse.indices.byteOffset)), n,
                                      isize, false, stride, who + " sparse indices");
    const unsigned char* val = locate(a.sparse.values.bufferView, size_t(std::max(0, a.sparse.values.byteOffset)), n,
                                      size, false, stride, who + " sparse values");
    for (size_t k = 0; k < n; ++k) {
      uint32_t i = little_endian(idx + k * isize, isize);
      if (i >= a.count)
        fail(who + ": sparse index " + std::to_string(i) + " past the count " + std::to_string(a.count));
      put(i, val + k * size);
    }
  }

  const tinygltf::Model& m_;
};

// --- meshes ----------------------------------------------------------------------------------------------------

/// A glTF mesh in its own space: all its triangle primitives, read once however many nodes instance it.
struct LocalMesh {
  std::vector<vec3> positions, normals;  ///< normals: one per position; zero where the primitive has none
  std::vector<uvec3> triangles;
  std::vector<int> materials;            ///< glTF material per triangle (-1: none)
};

const char* mode_name(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS: return "points";
    case TINYGLTF_MODE_LINE: return "lines";
    case TINYGLTF_MODE_LINE_LOOP: return "line loop";
    case TINYGLTF_MODE_LINE_STRIP: return "line strip";
    default: return "unknown mode";
  }
}

LocalMesh read_mesh(const tinygltf::Model& model, size_t mesh_index, Reader& reader,
                    std::vector<std::string>& warnings, const std::string& path) {
  const tinygltf::Mesh& mesh = model.meshes[mesh_index];
  std::string mname = name_of("mesh", mesh_index, mesh.name);
  LocalMesh out;
  std::map<std::string, int> skipped;
  for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
    const tinygltf::Primitive& prim = mesh.primitives[pi];
    int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      ++skipped[mode_name(mode)];
      continue;
    }
    std::string who = mname + " primitive " + std::to_string(pi);
    auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) fail(who + ": no POSITION attribute");
    std::vector<vec3> positions = reader.vec3s(pos->second, who + ": POSITION");
    for (const vec3& p : positions)
      if (!is_finite(p)) fail(who + ": non-finite vertex position");
    std::vector<vec3> normals;
    if (auto n = prim.attributes.find("NORMAL"); n != prim.attributes.end()) {
      normals = reader.vec3s(n->second, who + ": NORMAL");
      if (normals.size() != positions.size()) fail(who + ": NORMAL and POSITION counts differ");
    }
    std::vector<uint32_t> index;
    if (prim.indices >= 0) {
      index = reader.indices(prim.indices, who + ": indices");
      for (uint32_t i : index)
        if (i >= positions.size())
          fail(who + ": index " + std::to_string(i) + " past the vertex count " + std::to_string(positions.size()));
    } else {
      index.resize(positions.size());
      for (size_t i = 0; i < index.size(); ++i) index[i] = uint32_t(i);
    }
    if (prim.material >= 0 && size_t(prim.material) >= model.materials.size())
      fail(who + ": material " + std::to_string(prim.material) + " out of range");
    if (out.positions.size() + positions.size() > size_t(UINT32_MAX)) fail(mname + ": too many vertices");
    uint32_t base = uint32_t(out.positions.size());
    auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
      out.triangles.push_back(uvec3(base + a, base + b, base + c));
      out.materials.push_back(prim.material);
    };
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      for (size_t i = 0; i + 2 < index.size(); i += 3) add(index[i], index[i + 1], index[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {  // every other triangle reversed to keep the winding
      for (size_t i = 0; i + 2 < index.size(); ++i)
        i % 2 == 0 ? add(index[i], index[i + 1], index[i + 2]) : add(index[i + 1], index[i], index[i + 2]);
    } else {
      for (size_t i = 1; i + 1 < index.size(); ++i) add(index[0], index[i], index[i + 1]);
    }
    out.positions.insert(out.positions.end(), positions.begin(), positions.end());
    if (normals.empty()) normals.assign(positions.size(), vec3(0.0f));
    out.normals.insert(out.normals.end(), normals.begin(), normals.end());
  }
  for (auto& [mode, count] : skipped)
    warnings.push_back(path + ": " + mname + ": " + std::to_string(count) + " primitive" + (count == 1 ? "" : "s") +
                       " in mode '" + mode + "' skipped (only triangles are rendered)");
  return out;
}

// --- materials -------------------------------------------------------------------------------------------------

double number_in(const tinygltf::ExtensionMap& ext, const char* extension, const char* key, double fallback) {
  auto it = ext.find(extension);
  if (it == ext.end() || !it->second.Has(key)) return fallback;
  const tinygltf::Value& v = it->second.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

std::string num(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g", v);
  return s;
}

std::string triple(vec3 v) {
  char s[96];
  std::snprintf(s, sizeof s, "(%.3g, %.3g, %.3g)", v.x, v.y, v.z);
  return s;
}

class MaterialMapper {
 public:
  MaterialMapper(const tinygltf::Model& model, const ImageMeans& means, const std::string& path)
      : m_(model), means_(means), path_(path) {}

  Material operator()(size_t index, std::vector<std::string>& warnings) const {
    const tinygltf::Material& g = m_.materials[index];
    std::string mname = name_of("material", index, g.name);
    std::vector<std::string> notes;
    Material out;
    out.name = g.name.empty() ? "material" + std::to_string(index) : g.name;
    const auto& pbr = g.pbrMetallicRoughness;
    vec3 base(1.0f);
    if (!pbr.baseColorFactor.empty()) {
      if (pbr.baseColorFactor.size() != 4) fail(mname + ": baseColorFactor must have 4 numbers");
      base = checked(vec3(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]), mname,
                     "baseColorFactor");
    }
    base *= texture_mean(pbr.baseColorTexture.index, mname, "base colour", notes);
    double metallic = pbr.metallicFactor, roughness = pbr.roughnessFactor;
    if (!std::isfinite(metallic) || !std::isfinite(roughness)) fail(mname + ": non-finite metallic or roughness");
    if (pbr.metallicRoughnessTexture.index >= 0) notes.push_back("metallicRoughnessTexture ignored");
    double transmission = number_in(g.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0);
    double ior = number_in(g.extensions, "KHR_materials_ior", "ior", 1.5);
    if (!(ior > 0.0) || !std::isfinite(ior)) {
      notes.push_back("ior " + num(ior) + " replaced by 1.5");
      ior = 1.5;
    }
    if (transmission >= 0.5) {
      out.type = MaterialType::glass;
      out.ior = float(ior);
      out.albedo = vec3(1.0f);
      if (transmission < 1.0) notes.push_back("transmission " + num(transmission) + " as clear glass");
    } else if (metallic >= 0.5 && roughness <= kMirrorRoughness) {
      out.type = MaterialType::specular;
      out.albedo = base;
      if (roughness > kSmoothRoughness) notes.push_back("roughness " + num(roughness) + " as a mirror");
    } else {
      out.type = MaterialType::diffuse;
      out.albedo = base;
      if (metallic >= 0.5 && roughness < kRoughRoughness)
        notes.push_back("metal with roughness " + num(roughness) + " as diffuse");
    }
    if (max_component(out.albedo) > 1.0f) notes.push_back("albedo above 1 does not conserve energy");
    vec3 emissive(0.0f);
    if (!g.emissiveFactor.empty()) {
      if (g.emissiveFactor.size() != 3) fail(mname + ": emissiveFactor must have 3 numbers");
      emissive = checked(vec3(g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]), mname, "emissiveFactor");
    }
    double strength = number_in(g.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
    if (!(strength >= 0.0) || !std::isfinite(strength)) fail(mname + ": emissiveStrength must be >= 0 and finite");
    if (max_component(emissive) > 0.0f) emissive *= texture_mean(g.emissiveTexture.index, mname, "emissive", notes);
    out.emission = emissive * float(strength);
    if (!is_finite(out.emission)) fail(mname + ": emission overflows");
    if (g.normalTexture.index >= 0 || g.occlusionTexture.index >= 0) notes.push_back("normal/occlusion maps ignored");
    if (g.alphaMode != "OPAQUE" && !g.alphaMode.empty()) notes.push_back("alphaMode " + g.alphaMode + " ignored");
    if (!notes.empty()) {
      std::string joined;
      for (const std::string& n : notes) joined += (joined.empty() ? "" : "; ") + n;
      warnings.push_back(path_ + ": " + mname + " approximated: " + joined);
    }
    return out;
  }

 private:
  static vec3 checked(vec3 v, const std::string& mname, const char* key) {
    if (!is_finite(v) || min_component(v) < 0.0f) fail(mname + ": " + key + " must be finite and not negative");
    return v;
  }

  /// The mean colour of texture `index` (white when there is none or it cannot be decoded), noting the
  /// approximation.
  vec3 texture_mean(int index, const std::string& mname, const char* which, std::vector<std::string>& notes) const {
    if (index < 0) return vec3(1.0f);
    if (size_t(index) >= m_.textures.size())
      fail(mname + ": " + which + " texture " + std::to_string(index) + " out of range");
    int image = m_.textures[size_t(index)].source;
    if (auto it = means_.mean.find(image); it != means_.mean.end()) {
      notes.push_back(std::string(which) + " texture as its mean colour " + triple(it->second));
      return it->second;
    }
    auto why = means_.failure.find(image);
    notes.push_back(std::string(which) + " texture ignored (image " + std::to_string(image) + ": " +
                    (why != means_.failure.end() ? why->second : "not loaded") + ")");
    return vec3(1.0f);
  }

  const tinygltf::Model& m_;
  const ImageMeans& means_;
  const std::string& path_;
};

// --- nodes -----------------------------------------------------------------------------------------------------

dmat4 local_matrix(const tinygltf::Node& n, size_t index) {
  std::string who = name_of("node", index, n.name);
  auto finite = [&](const std::vector<double>& v, size_t size, const char* key) {
    if (!v.empty() && v.size() != size) fail(who + ": " + key + " must have " + std::to_string(size) + " numbers");
    for (double x : v)
      if (!std::isfinite(x)) fail(who + ": non-finite " + key);
    return !v.empty();
  };
  if (finite(n.matrix, 16, "matrix")) {
    dmat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(4 * c + r)];  // column-major, as glTF stores it
    return m;
  }
  dmat4 t(1.0), r(1.0), s(1.0);
  if (finite(n.translation, 3, "translation")) t[3] = dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
  if (finite(n.rotation, 4, "rotation")) {
    glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF stores x, y, z, w
    double len = glm::length(q);
    if (!(len > 0.0) || !std::isfinite(len)) fail(who + ": rotation quaternion has zero length");
    r = glm::mat4_cast(q / len);
  }
  if (finite(n.scale, 3, "scale")) s = glm::scale(dmat4(1.0), dvec3(n.scale[0], n.scale[1], n.scale[2]));
  return t * r * s;
}

struct Instance {
  size_t node;
  dmat4 world;
};

/// Every node of the scene's trees with its world matrix, parents before children (depth first, in file order).
/// Iterative, so a deep chain cannot overflow the stack; a node met twice is a cycle or a node with two parents,
/// both invalid glTF and both refused (the second would also let a small file instance a subtree exponentially).
std::vector<Instance> walk_nodes(const tinygltf::Model& model, const std::vector<int>& roots) {
  enum : uint8_t { unseen, open, done };
  std::vector<uint8_t> state(model.nodes.size(), unseen);
  std::vector<Instance> out;
  struct Frame {
    size_t node;
    size_t next_child;
    dmat4 world;
  };
  std::vector<Frame> stack;
  auto enter = [&](int index, const dmat4& parent, const std::string& from) {
    if (index < 0 || size_t(index) >= model.nodes.size())
      fail(from + ": node " + std::to_string(index) + " out of range (" + std::to_string(model.nodes.size()) +
           " nodes)");
    size_t i = size_t(index);
    if (state[i] == open) fail("cyclic node graph: node " + std::to_string(i) + " is its own ancestor");
    if (state[i] == done) fail("node " + std::to_string(i) + " has more than one parent");
    state[i] = open;
    dmat4 world = parent * local_matrix(model.nodes[i], i);
    out.push_back({i, world});
    stack.push_back({i, 0, world});
  };
  for (int root : roots) {
    enter(root, dmat4(1.0), "scene");
    while (!stack.empty()) {
      Frame& f = stack.back();
      const tinygltf::Node& n = model.nodes[f.node];
      if (f.next_child < n.children.size()) {
        int child = n.children[f.next_child++];
        dmat4 world = f.world;  // `f` may move when enter() grows the stack
        enter(child, world, "node " + std::to_string(f.node));
      } else {
        state[f.node] = done;
        stack.pop_back();
      }
    }
  }
  return out;
}

std::vector<int> scene_roots(const tinygltf::Model& model, std::vector<std::string>& warnings,
                             const std::string& path) {
  if (model.scenes.empty()) {  // no scene: every node that is nobody's child
    std::vector<bool> child(model.nodes.size(), false);
    for (const tinygltf::Node& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = true;
    std::vector<int> roots;
    for (size_t i = 0; i < child.size(); ++i)
      if (!child[i]) roots.push_back(int(i));
    return roots;
  }
  int s = model.defaultScene;
  if (s >= int(model.scenes.size())) fail("default scene " + std::to_string(s) + " out of range");
  if (s < 0) s = 0;
  if (model.scenes.size() > 1)
    warnings.push_back(path + ": " + std::to_string(model.scenes.size()) + " scenes: only scene " +
                       std::to_string(s) + " is loaded");
  return model.scenes[size_t(s)].nodes;
}

/// The perspective camera of a node: eye at its origin looking down its -z with +y up (glTF 2.0, 3.10).
std::optional<Camera> node_camera(const tinygltf::Camera& c, const dmat4& world) {
  if (c.type != "perspective") return std::nullopt;
  double yfov = c.perspective.yfov;
  if (!(yfov > 0.0 && yfov < glm::pi<double>())) return std::nullopt;
  dvec3 eye(world[3]), forward(world * dvec4(0, 0, -1, 0)), up(world * dvec4(0, 1, 0, 0));
  double fl = glm::length(forward), ul = glm::length(up);
  if (!is_finite(vec3(eye)) || !(fl > 0.0) || !std::isfinite(fl) || !(ul > 0.0) || !std::isfinite(ul))
    return std::nullopt;
  forward /= fl;
  up /= ul;
  if (!(glm::length(glm::cross(forward, up)) > 1e-6)) return std::nullopt;
  Camera cam;
  cam.eye = vec3(eye);
  cam.target = vec3(eye + forward);
  cam.up = vec3(up);
  cam.fov_deg = float(glm::degrees(yfov));
  return cam;
}

const std::set<std::string>& supported_required_extensions() {
  static const std::set<std::string> s = {"KHR_materials_emissive_strength", "KHR_materials_ior",
                                          "KHR_materials_transmission", "KHR_mesh_quantization",
                                          "KHR_texture_transform"};
  return s;
}

/// A .glb's 12-byte header, checked before tinygltf sees it so the common failures read plainly.
void check_glb_header(std::string_view bytes) {
  if (bytes.size() < 12)
    fail("truncated .glb: " + std::to_string(bytes.size()) + " bytes, the header alone needs 12");
  if (bytes.substr(0, 4) != "glTF") fail("not a binary glTF: wrong magic (expected 'glTF')");
  auto u32 = [&](size_t at) { return little_endian(reinterpret_cast<const unsigned char*>(bytes.data()) + at, 4); };
  if (u32(4) != 2) fail("unsupported .glb version " + std::to_string(u32(4)) + " (expected 2)");
  if (u32(8) > bytes.size())
    fail("truncated .glb: the header says " + std::to_string(u32(8)) + " bytes, the file has " +
         std::to_string(bytes.size()));
}

/// The first line of tinygltf's message, without its trailing newline.
std::string first_line(const std::string& s) {
  size_t start = s.find_first_not_of("\r\n");
  if (start == std::string::npos) return "cannot parse";
  size_t end = s.find_first_of("\r\n", start);
  return s.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

bool is_binary(const std::string& path, std::string_view bytes) {
  const std::string ext = lower_extension(path);
  return ext == ".glb" || (ext != ".gltf" && bytes.substr(0, 4) == "glTF");
}

GltfData read_model(const std::string& path, bool use_materials) {
  Result<std::string> bytes = read_text_file(path);
  if (!bytes) fail(bytes.error());  // already "PATH: ..."; read_gltf does not prefix it again
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  ImageMeans means;
  loader.SetImageLoader(&decode_image_mean, &means);
  loader.SetFsCallbacks({&file_exists, &expand_path, &read_file_callback, &write_whole_file, nullptr});
  std::string err, warn;
  std::string dir = std::filesystem::path(path).parent_path().string();
  bool ok = false;
  if (is_binary(path, *bytes)) {
    check_glb_header(*bytes);
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes->data()),
                                     unsigned(bytes->size()), dir);
  } else {
    if (bytes->find('\0') != std::string::npos) fail("binary data in a .gltf (JSON) file");
    ok = loader.LoadASCIIFromString(&model, &err, &warn, bytes->data(), unsigned(bytes->size()), dir);
  }
  if (!ok) fail(first_line(err));
  std::string().swap(*bytes);

  GltfData out;
  std::vector<std::string>& warnings = out.geometry.warnings;
  for (const std::string& e : model.extensionsRequired)
    if (!supported_required_extensions().count(e)) fail("unsupported required extension '" + e + "'");
  if (!model.skins.empty() || !model.animations.empty())
    warnings.push_back(path + ": skins and animations ignored (the rest pose is rendered)");

  std::vector<Instance> nodes = walk_nodes(model, scene_roots(model, warnings, path));
  Reader reader(model);
  std::map<size_t, LocalMesh> local;  // meshes read so far
  std::map<int, uint32_t> material_ids;
  MaterialMapper mapper(model, means, path);
  auto material_id = [&](int gltf_material) -> uint32_t {
    if (!use_materials) return 0;
    auto [it, inserted] = material_ids.try_emplace(gltf_material, uint32_t(out.geometry.materials.size()));
    if (inserted)
      out.geometry.materials.push_back(gltf_material < 0 ? Material{"default"}
                                                         : mapper(size_t(gltf_material), warnings));
    return it->second;
  };

  Mesh& mesh = out.geometry.mesh;
  mesh.name = path;
  size_t triangles_read = 0, degenerate = 0;
  bool any_normals = false;
  std::vector<Instance> cameras;
  for (const Instance& inst : nodes) {
    const tinygltf::Node& node = model.nodes[inst.node];
    if (node.camera >= 0) {
      if (size_t(node.camera) >= model.cameras.size())
        fail(name_of("node", inst.node, node.name) + ": camera " + std::to_string(node.camera) + " out of range");
      cameras.push_back(inst);
    }
    if (node.mesh < 0) continue;
    if (size_t(node.mesh) >= model.meshes.size())
      fail(name_of("node", inst.node, node.name) + ": mesh " + std::to_string(node.mesh) + " out of range");
    auto it = local.find(size_t(node.mesh));
    if (it == local.end())
      it = local.emplace(size_t(node.mesh), read_mesh(model, size_t(node.mesh), reader, warnings, path)).first;
    const LocalMesh& lm = it->second;
    triangles_read += lm.triangles.size();
    if (triangles_read > kMaxTriangles)
      fail("more than " + std::to_string(kMaxTriangles) + " triangles over all mesh instances");
    mat3 linear(inst.world);
    vec3 translation(inst.world[3]);
    mat3 normal_matrix = glm::transpose(glm::inverse(linear));
    bool mirrored = glm::determinant(inst.world) < 0.0;
    if (mesh.positions.size() + lm.positions.size() > size_t(UINT32_MAX)) fail("too many vertices");
    uint32_t base = uint32_t(mesh.positions.size());
    for (const vec3& p : lm.positions) {
      vec3 w = linear * p + translation;
      if (!is_finite(w)) fail(name_of("node", inst.node, node.name) + ": non-finite transformed position");
      mesh.positions.push_back(w);
    }
    for (const vec3& n : lm.normals) {
      vec3 m = normal_matrix * n;
      float len = glm::length(m);
      mesh.normals.push_back(len > 0.0f && std::isfinite(len) ? m / len : vec3(0.0f));
    }
    for (size_t t = 0; t < lm.triangles.size(); ++t) {
      uvec3 tri = lm.triangles[t] + uvec3(base);
      if (mirrored) std::swap(tri.y, tri.z);
      dvec3 a(mesh.positions[tri.x]), b(mesh.positions[tri.y]), c(mesh.positions[tri.z]);
      dvec3 gn = glm::cross(b - a, c - a);
      if (!(glm::dot(gn, gn) > 0.0)) {
        ++degenerate;
        continue;
      }
      mesh.indices.push_back(tri);
      mesh.materials.push_back(material_id(lm.materials[t]));
      bool shaded = mesh.normals[tri.x] != vec3(0.0f) && mesh.normals[tri.y] != vec3(0.0f) &&
                    mesh.normals[tri.z] != vec3(0.0f);
      if (shaded) {
        mesh.normal_indices.push_back(tri);
        any_normals = true;
      } else {  // a flat normal of its own, as OBJ faces without vn in a mesh that has them
        mesh.normal_indices.push_back(uvec3(uint32_t(mesh.normals.size())));
        mesh.normals.push_back(vec3(glm::normalize(gn)));
      }
    }
  }
  if (degenerate > 0)
    warnings.push_back(path + ": " + std::to_string(degenerate) + " degenerate (zero-area) triangle" +
                       (degenerate == 1 ? "" : "s") + " dropped");
  if (mesh.indices.empty()) fail("no triangles (the default scene has no triangle meshes)");
  if (!any_normals) {
    mesh.normals.clear();
    mesh.normal_indices.clear();
  }

  AABB bounds;
  for (const vec3& p : mesh.positions) bounds.extend(p);
  for (const Instance& inst : cameras) {
    const tinygltf::Camera& c = model.cameras[size_t(model.nodes[inst.node].camera)];
    std::optional<Camera> cam = node_camera(c, inst.world);
    if (!cam) {
      warnings.push_back(path + ": " + name_of("camera", size_t(model.nodes[inst.node].camera), c.name) +
                         " skipped (not perspective, or a degenerate yfov or node transform)");
      continue;
    }
    // Aim at the depth of the scene's center, so the viewer orbits around something sensible.
    vec3 forward = cam->target - cam->eye;
    float depth = glm::dot(bounds.center() - cam->eye, forward);
    float extent = glm::length(bounds.extent());
    if (!(depth > 1e-3f * extent) || !std::isfinite(depth)) depth = std::max(extent, 1.0f);
    cam->target = cam->eye + depth * forward;
    out.cameras.push_back(*cam);
  }
  return out;
}

}  // namespace

Result<GltfData> read_gltf(const std::string& path, bool use_materials) {
  try {
    return read_model(path, use_materials);
  } catch (const GltfError& e) {
    return Error{e.message.starts_with(path + ": ") ? e.message : path + ": " + e.message};
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
}

Result<Scene> load_gltf_scene(const std::string& path) {
  Result<GltfData> data = read_gltf(path, true);
  if (!data) return Error{data.error()};
  Scene scene;
  scene.source = path;
  scene.cameras = std::move(data->cameras);
  if (!scene.cameras.empty()) scene.camera = scene.cameras.front();
  append_obj(scene, std::move(data->geometry), -1);
  return scene;
}

}  // namespace pt
