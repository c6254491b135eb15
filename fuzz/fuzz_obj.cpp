// libFuzzer: OBJ text (with an MTL written beside it from the second half of the input) must load or give one
// error line. The loader reads files, so each input is written to a per-process temporary directory.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene/load.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string dir = [] {
    std::string d = "/tmp/ptview-fuzz-obj-" + std::to_string(::getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  std::string text(reinterpret_cast<const char*>(data), size);
  size_t split = text.find("\nnewmtl");
  std::ofstream(dir + "/m.obj", std::ios::binary) << "mtllib m.mtl\n" << text.substr(0, split);
  std::ofstream(dir + "/m.mtl", std::ios::binary) << (split == std::string::npos ? "" : text.substr(split));
  pt::Result<pt::Scene> r = pt::load_scene(dir + "/m.obj");
  if (!r.ok() && (r.error().empty() || r.error().find('\n') != std::string::npos)) __builtin_trap();
  return 0;
}
