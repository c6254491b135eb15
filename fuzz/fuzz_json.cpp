// libFuzzer: scene JSON text must give a scene or one error line, never crash or hang.
#include <cstdint>
#include <string>

#include "scene/load.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  pt::Result<pt::Scene> r = pt::parse_json_scene(text, "/nonexistent-dir/fuzz.json");
  if (!r.ok() && (r.error().empty() || r.error().find('\n') != std::string::npos)) __builtin_trap();
  return 0;
}
