#include "app/app.h"

#include <chrono>
#include <cstdio>

#include "scene/load.h"

#ifdef PTVIEW_HAS_VIEWER
#include "view/viewer.h"
#endif

namespace pt {

int run_app(int argc, const char* const* argv) {
  ParseOutcome parsed = parse_command_line(argc, argv);
  if (!parsed.options) {
    if (parsed.exit_code == 0) std::fputs(parsed.message.c_str(), stdout);
    else std::fprintf(stderr, "ptview: error: %s\n", parsed.message.c_str());
    return parsed.exit_code;
  }
  const AppOptions& options = *parsed.options;
  const auto load_start = std::chrono::steady_clock::now();
  Result<Scene> scene = options.scene_path.empty() ? load_builtin_scene(kDefaultSceneName)
                                                   : load_scene(options.scene_path);
  if (!scene) {
    std::fprintf(stderr, "ptview: error: %s\n", scene.error().c_str());
    return 2;
  }
  const double load_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_start).count();
  if (options.headless()) return run_headless(options, *scene, load_ms);
#ifdef PTVIEW_HAS_VIEWER
  return run_viewer(options.render, options.display, options.viewer, std::move(*scene));
#else
  std::fprintf(stderr, "ptview: error: this build has no viewer; render headless with --frames N\n");
  return 2;
#endif
}

}  // namespace pt
