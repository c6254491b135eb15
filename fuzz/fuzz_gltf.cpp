// libFuzzer: glTF input must load or give one error line, never crash or hang. Inputs starting with "glTF" are
// written as a .glb, others as a .gltf; a ".bin" beside it holds the same bytes, so external buffer and image URIs
// ("m.bin") resolve to something. The loader reads files, so each input goes to a per-process temporary directory.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene/load.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string dir = [] {
    std::string d = "/tmp/ptview-fuzz-gltf-" + std::to_string(::getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  std::string bytes(reinterpret_cast<const char*>(data), size);
  std::string path = dir + (bytes.rfind("glTF", 0) == 0 ? "/m.glb" : "/m.gltf");
  std::ofstream(path, std::ios::binary) << bytes;
  std::ofstream(dir + "/m.bin", std::ios::binary) << bytes;
  pt::Result<pt::Scene> r = pt::load_scene(path);
  if (!r.ok() && (r.error().empty() || r.error().find('\n') != std::string::npos)) __builtin_trap();
  return 0;
}
