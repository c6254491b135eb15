#include "app/app.h"

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
  Result<Scene> scene = options.scene_path.empty() ? load_builtin_scene(kDefaultSceneName)
                                                   : load_scene(options.scene_path);
  if (!scene) {
    std::fprintf(stderr, "ptview: error: %s\n", scene.error().c_str());
    return 2;
  }
  if (options.camera) {
    if (std::string e = select_camera(*scene, size_t(*options.camera)); !e.empty()) {
      std::fprintf(stderr, "ptview: error: --camera: %s\n", e.c_str());
      return 2;
    }
  }
  if (options.headless()) return run_headless(options, *scene);
#ifdef PTVIEW_HAS_VIEWER
  return run_viewer(options.render, options.display, options.viewer, std::move(*scene));
#else
  std::fprintf(stderr, "ptview: error: this build has no viewer; render headless with --frames N\n");
  return 2;
#endif
}

}  // namespace pt
