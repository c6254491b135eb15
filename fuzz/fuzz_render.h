#pragma once
// The whole-pipeline fuzz harness (fuzz_render.cpp), shared with its regression test (tests/app): load a scene,
// build the BVH, render it small with every integrator and light-sampling mode, and say what went wrong.
//
// Input format: scene JSON text, optionally followed by side files, each introduced by a line "--- NAME" where
// NAME is one of kSideFiles. The JSON is read as DIR/s.json, so {"type":"mesh","file":"m.obj"} loads the OBJ text
// carried in the same input (and "mtllib m.mtl" in it the MTL). Side files an input does not carry are removed
// before it runs, so every input is reproducible on its own.
//
// glTF joins through the same side files: {"type":"mesh","file":"m.gltf"} loads "--- m.gltf" (JSON, with its
// buffer in "--- m.bin" or a data URI).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "render/film.h"
#include "render/render_scene.h"
#include "render/renderer.h"
#include "scene/load.h"

namespace pt::fuzz {

inline constexpr std::string_view kSideFiles[] = {"m.obj", "m.mtl", "m.gltf", "m.bin"};

/// Render settings of every input: 8x8 pixels, 2 spp, max depth 4, one thread.
inline constexpr int kRenderSize = 8;
inline constexpr int kRenderSpp = 2;
inline constexpr int kRenderMaxDepth = 4;
/// Scenes larger than this are loaded but not built or rendered: a valid huge mesh ("generate" allows 2^25
/// triangles) is not a defect, and a harness that builds it tests only the machine's memory.
inline constexpr size_t kMaxTriangles = size_t(1) << 14;

/// Rays one render may cast: per camera sample, per path vertex (max depth + 1 of them, plus the camera ray) at
/// most one bounce ray and one shadow ray. More means a path loop that ignores its depth bound.
inline constexpr uint64_t kRayBudget =
    uint64_t(kRenderSize) * kRenderSize * kRenderSpp * 2 * (uint64_t(kRenderMaxDepth) + 2);

/// Returns the JSON part of `text` and writes its side files into `dir`.
inline std::string split_input(std::string_view text, const std::filesystem::path& dir) {
  for (std::string_view name : kSideFiles) std::filesystem::remove(dir / name);
  std::string json;
  std::ofstream* out = nullptr;
  std::ofstream side;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    bool header = false;
    if (line.starts_with("--- "))
      for (std::string_view name : kSideFiles)
        if (line.substr(4) == name) {
          side.close();
          side.open(dir / name, std::ios::binary | std::ios::app);
          out = &side;
          header = true;
        }
    if (!header) {
      std::string_view piece = end < text.size() ? text.substr(pos, end - pos + 1) : line;
      if (out)
        out->write(piece.data(), std::streamsize(piece.size()));
      else
        json.append(piece);
    }
    pos = end + 1;
  }
  return json;
}

/// Runs one input; returns "" or what went wrong (a trap in the fuzzer, a failure in the regression test).
inline std::string check_render_input(std::string_view text, const std::filesystem::path& dir) {
  std::string json = split_input(text, dir);
  std::string path = (dir / "s.json").string();
  Result<Scene> loaded = parse_json_scene(json, path);
  if (!loaded) {
    const std::string& e = loaded.error();
    return e.empty() || e.find('\n') != std::string::npos ? "load error not one line: " + e : "";
  }
  Scene& scene = *loaded;
  finalize_scene(scene);
  if (scene.triangle_count() > kMaxTriangles) return "";
  RenderScene rs = make_render_scene(scene);
  static Renderer renderer(1);
  for (IntegratorKind k : {IntegratorKind::mis, IntegratorKind::nee, IntegratorKind::bsdf})
    for (LightSampling ls : {LightSampling::area, LightSampling::solid_angle, LightSampling::automatic}) {
      RenderParams p;
      p.width = p.height = kRenderSize;
      p.spp_per_frame = kRenderSpp;
      p.max_depth = kRenderMaxDepth;
      p.integrator = k;
      p.light_sampling = ls;
      p.threads = 1;
      Film film(p.width, p.height);
      RenderCounters c;
      renderer.render_frame(rs, p, film, 0, c);
      std::string mode = "integrator " + std::to_string(int(k)) + " light sampling " + std::to_string(int(ls));
      if (c.rays() > kRayBudget) return mode + ": " + std::to_string(c.rays()) + " rays, budget " +
                                        std::to_string(kRayBudget);
      if (c.samples != uint64_t(kRenderSize) * kRenderSize * kRenderSpp) return mode + ": wrong sample count";
      for (size_t i = 0; i < film.count.size(); ++i)
        if (!is_finite(film.mean(i))) return mode + ": non-finite pixel " + std::to_string(i);
    }
  return "";
}

}  // namespace pt::fuzz
