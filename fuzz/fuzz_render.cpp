// libFuzzer: a scene JSON (with OBJ/MTL text carried in the same input, see fuzz_render.h) must load or give one
// error line, and then build and render without a crash, a sanitizer report, a non-finite pixel or more rays than
// its depth bound allows. Allocation caps come from libFuzzer (-malloc_limit_mb, -rss_limit_mb in scripts/fuzz.sh).
#include <unistd.h>

#include <cstdint>
#include <cstdio>

#include "fuzz_render.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = "/tmp/ptview-fuzz-render-" + std::to_string(::getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  std::string failure = pt::fuzz::check_render_input(std::string_view(reinterpret_cast<const char*>(data), size), dir);
  if (!failure.empty()) {
    std::fprintf(stderr, "fuzz_render: %s\n", failure.c_str());
    __builtin_trap();
  }
  return 0;
}
