#pragma once
/// Writes small glTF 2.0 files for tests (and the large-scene benchmark): one binary buffer built up view by view,
/// the JSON as nlohmann::json, saved as .gltf with the buffer as a base64 data URI or a .bin file, or as .glb.
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/math.h"

namespace pt::test {

inline std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == in.size()) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

struct GltfBuilder {
  std::string bin;
  nlohmann::json j = {{"asset", {{"version", "2.0"}}}};

  GltfBuilder() {
    for (const char* k : {"bufferViews", "accessors", "meshes", "nodes", "materials"}) j[k] = nlohmann::json::array();
    j["scenes"] = {{{"nodes", nlohmann::json::array()}}};
    j["scene"] = 0;
  }

  /// Appends raw bytes (4-byte aligned) as a buffer view; returns its index.
  int view(const void* data, size_t bytes, size_t stride = 0) {
    while (bin.size() % 4) bin += '\0';
    nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (stride) v["byteStride"] = stride;
    bin.append(static_cast<const char*>(data), bytes);
    j["bufferViews"].push_back(v);
    return int(j["bufferViews"].size() - 1);
  }
  int accessor(int view_index, size_t offset, int component, size_t count, const char* type) {
    j["accessors"].push_back({{"bufferView", view_index}, {"byteOffset", offset}, {"componentType", component},
                              {"count", count}, {"type", type}});
    return int(j["accessors"].size() - 1);
  }
  int positions(const std::vector<vec3>& p) {
    return accessor(view(p.data(), p.size() * 12), 0, 5126, p.size(), "VEC3");
  }
  template <class T>
  int indices(const std::vector<T>& idx) {
    int component = sizeof(T) == 1 ? 5121 : sizeof(T) == 2 ? 5123 : 5125;
    return accessor(view(idx.data(), idx.size() * sizeof(T)), 0, component, idx.size(), "SCALAR");
  }
  /// A mesh of one primitive; `indices_acc` < 0 for none, `material` < 0 for none. Returns the mesh index.
  int mesh(int position_acc, int indices_acc = -1, int material = -1, int normal_acc = -1, int mode = 4) {
    nlohmann::json prim = {{"attributes", {{"POSITION", position_acc}}}, {"mode", mode}};
    if (normal_acc >= 0) prim["attributes"]["NORMAL"] = normal_acc;
    if (indices_acc >= 0) prim["indices"] = indices_acc;
    if (material >= 0) prim["material"] = material;
    j["meshes"].push_back({{"primitives", {prim}}});
    return int(j["meshes"].size() - 1);
  }
  int node(nlohmann::json n, bool root = true) {
    j["nodes"].push_back(std::move(n));
    int i = int(j["nodes"].size() - 1);
    if (root) j["scenes"][0]["nodes"].push_back(i);
    return i;
  }
  int material(nlohmann::json m) {
    j["materials"].push_back(std::move(m));
    return int(j["materials"].size() - 1);
  }

  nlohmann::json with_buffer(const std::string& uri) const {
    nlohmann::json out = j;
    out["buffers"] = {{{"byteLength", bin.size()}}};
    if (!uri.empty()) out["buffers"][0]["uri"] = uri;
    if (out["materials"].empty()) out.erase("materials");
    return out;
  }
  /// .gltf with the buffer embedded as a data URI.
  std::string embedded() const {
    return with_buffer("data:application/octet-stream;base64," + base64(bin)).dump();
  }
  /// .glb: header, JSON chunk (space padded), BIN chunk (zero padded).
  std::string glb() const {
    std::string json = with_buffer("").dump();
    while (json.size() % 4) json += ' ';
    std::string b = bin;
    while (b.size() % 4) b += '\0';
    std::string out;
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    out += "glTF";
    u32(2);
    u32(uint32_t(12 + 8 + json.size() + 8 + b.size()));
    u32(uint32_t(json.size()));
    out += "JSON";
    out += json;
    u32(uint32_t(b.size()));
    out += "BIN";
    out += '\0';
    out += b;
    return out;
  }
  /// .gltf next to a .bin file named `bin_name` (written too).
  void save_with_bin(const std::string& gltf_path, const std::string& bin_dir, const std::string& bin_name) const {
    std::ofstream(bin_dir + "/" + bin_name, std::ios::binary) << bin;
    std::ofstream(gltf_path, std::ios::binary) << with_buffer(bin_name).dump();
  }
};

inline void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace pt::test
