#include "app/app.h"

#include <chrono>
#include <cstdio>

#include "dist/cluster.h"
#include "scene/load.h"

#ifdef PTVIEW_HAS_VIEWER
#include "view/viewer.h"
#endif

namespace pt {

int run_app(int argc, const char* const* argv) {
  // Under mpirun every rank runs this; errors are agreed on collectively and only rank 0 prints.
  std::unique_ptr<Cluster> cluster = join_cluster();
  ParseOutcome parsed = parse_command_line(argc, argv);
  if (std::string err = cluster->first_error(parsed.options || parsed.exit_code == 0 ? "" : parsed.message);
      !err.empty())
    return report_error(*cluster, err);
  if (!parsed.options) {
    if (cluster->root()) std::fputs(parsed.message.c_str(), stdout);
    return parsed.exit_code;
  }
  AppOptions options = *parsed.options;
  if (options.render.threads == 0) options.render.threads = cluster->default_threads();
#ifndef PTVIEW_HAS_VIEWER
  if (cluster->ranks() > 1 && !options.headless())
    return report_error(*cluster, "this build has no viewer; render headless with --frames N");
#endif
  const auto load_start = std::chrono::steady_clock::now();
  Result<Scene> scene = options.scene_path.empty() ? load_builtin_scene(kDefaultSceneName)
                                                   : load_scene(options.scene_path);
  std::string load_error;
  if (!scene) {
    load_error = scene.error();
    // Every rank reads the scene itself; a file only rank 0's machine has is the usual cluster mistake.
    if (cluster->ranks() > 1)
      load_error += " (every MPI rank loads the scene: it must exist at this path on every node)";
  }
  const double load_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_start).count();
  if (std::string err = cluster->first_error(load_error); !err.empty()) return report_error(*cluster, err);
  if (options.camera) {
    if (std::string e = select_camera(*scene, size_t(*options.camera)); !e.empty())
      return report_error(*cluster, "--camera: " + e);
  }
  if (options.headless()) return run_headless(options, *scene, *cluster, load_ms);
#ifdef PTVIEW_HAS_VIEWER
  if (cluster->ranks() > 1) {  // the viewer offload: the window on rank 0, the other ranks render for it
    std::unique_ptr<OffloadChannel> channel = cluster->offload_channel();
    if (!cluster->root()) {
      *scene = Scene{};  // loaded for the collective check only: the workers render rank 0's posted scene
      return run_offload_worker(*channel, cluster->rank(), options.render.threads);
    }
    OffloadRoot offload(std::move(channel));  // its end (when run_viewer returns, on any path) ends the workers
    offload.set_ranks(cluster->ranks());
    return run_viewer(options.render, options.display, options.viewer, std::move(*scene), &offload);
  }
  return run_viewer(options.render, options.display, options.viewer, std::move(*scene));
#else
  std::fprintf(stderr, "ptview: error: this build has no viewer; render headless with --frames N\n");
  return 2;
#endif
}

}  // namespace pt
