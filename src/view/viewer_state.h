#pragma once
/// The viewer's state and actions, independent of how they are triggered (mouse, keys, panels, script).
#include <chrono>
#include <future>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/render_scene.h"
#include "render/session.h"
#include "view/viewer_hooks.h"

namespace pt {

using Clock = std::chrono::steady_clock;

/// A scene being loaded on a background thread: parsed and with its BVH built, ready to swap in.
struct LoadedScene {
  Scene scene;
  std::shared_ptr<const RenderGeometry> geo;
  double load_ms = 0.0;
};

/// Everything an edit touches. Restart tiers: display settings never restart; camera, material and light edits
/// restart accumulation over the same geometry (light edits refit it); loading builds new geometry off-thread.
struct ViewerState {
  RenderParams params;         ///< full-resolution parameters
  DisplaySettings display;
  ViewerHooks hooks;
  Scene scene;
  Camera home_camera;
  std::shared_ptr<const RenderGeometry> geo;
  std::shared_ptr<const RenderScene> render_scene;  ///< the one being rendered (for picking)
  std::unique_ptr<RenderSession> session;
  SessionFrame frame;          ///< latest frame shown
  int selected_material = -1;
  int preview_div = 4;         ///< first frame of every restart at this fraction of the resolution
  double full_res_frame_seconds = 0.0;

  // Measurements.
  std::map<uint64_t, Clock::time_point> restart_started;  ///< epoch -> time of the edit
  std::vector<double> restart_latency_ms;
  uint64_t ui_frames = 0;
  Clock::time_point start_time = Clock::now();
  double load_ms = 0.0;

  // Background work.
  std::future<Result<LoadedScene>> loading;
  std::string loading_path;
  std::string status;          ///< last message shown in the Scene panel
  std::vector<std::future<std::optional<Error>>> saves;

  /// Restarts accumulation with the current scene, camera, materials and parameters. The session shows a
  /// reduced-resolution first frame at once, so a camera drag (one restart per UI frame) stays fluid.
  void restart();
  /// Starts loading a scene file in the background; the current scene stays interactive.
  void start_load(const std::string& path);
  /// Swaps in a finished load, if any. Returns true if a new scene was installed.
  bool poll_load();
  /// Material index of the object seen through full-resolution pixel (x, y), or -1.
  int pick(int x, int y) const;
  /// Index of the quad used as "the" rectangle light (the first emissive quad), or -1.
  int light_quad() const;
  /// Resizes the rectangle light about its center (refit, no rebuild) and restarts.
  void set_light_size(float width, float height);
  /// Saves the current mean on a background thread.
  void save_current(const std::string& path);
  std::string stats_json() const;
};

}  // namespace pt
