#pragma once
/// The viewer's state and the one function that changes it, apply(Edit), independent of how an edit was made
/// (mouse, keys, panels, script). No GL or window here: the tier tests drive it directly.
#include <atomic>
#include <chrono>
#include <deque>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/render_scene.h"
#include "render/session.h"
#include "scene/scene_lights.h"
#include "view/edit.h"
#include "view/offload.h"
#include "view/viewer_hooks.h"

namespace pt {

using Clock = std::chrono::steady_clock;

/// A scene loaded on a background thread: parsed and with its BVH built, ready to swap in.
struct LoadedScene {
  Scene scene;
  std::shared_ptr<const RenderGeometry> geo;
  double load_ms = 0.0;
};

/// How far a background load got, for the Scene panel.
struct LoadProgress {
  std::atomic<int> stage{0};  ///< 0 parsing, 1 building the BVH
  std::atomic<size_t> triangles{0};
  Clock::time_point started = Clock::now();
};

inline constexpr double kCompareSliceSeconds = 0.1;

struct ViewerState {
  RenderParams params;         ///< full-resolution parameters
  DisplaySettings display;
  DisplayMode display_mode = DisplayMode::image;
  bool display_dirty = true;   ///< the shown image must be rebuilt from `frame` (a display-mode change)
  AdaptiveParams adaptive;     ///< adaptive sampling as last applied to the session
  int target_spp = 0;          ///< "stop at spp" as last applied to both sides (0: never stop)
  std::optional<Image> reference;  ///< --reference, for the true relMSE and the reference-error mode
  /// (seconds, est relMSE) of the current epoch's full frames, for the Stats panel's error-vs-time plot.
  std::vector<std::pair<double, double>> error_history;
  // Equal-time A/B compare (issue 12): B renders the same scene and camera with `compare`'s settings, A and B
  // taking turns in wall-clock slices of kCompareSliceSeconds (tick_compare); any restart restarts both.
  std::optional<CompareConfig> compare;
  std::unique_ptr<RenderSession> session_b;  ///< kept, paused, after compare off (never joined on the UI thread)
  SessionFrame frame_b;
  double frame_b_rel_mse = std::numeric_limits<double>::quiet_NaN();
  float divider = 0.5f;        ///< A left of this fraction of the image width, B right
  bool paused = false;         ///< the user's pause (both sides)
  bool slice_b = false;        ///< B's turn
  Clock::time_point slice_start = Clock::now();
  Scene scene;
  Camera home_camera;
  std::shared_ptr<const RenderGeometry> geo;
  std::shared_ptr<const RenderScene> render_scene;  ///< the one being rendered (picking reads it)
  std::unique_ptr<RenderSession> session;           ///< null in tests that only check tiers
  /// Under mpirun: the other ranks render too (view/offload.h); every restart posts an epoch. Set before init.
  OffloadRoot* offload = nullptr;
  SessionFrame frame;          ///< latest frame shown
  std::vector<SceneLight> lights;  ///< find_scene_lights(scene), kept stable between material edits
  std::vector<Material> loaded_materials;  ///< as loaded: a saved scene names a mesh's file while they are unedited
  int selected_material = -1;
  int selected_light = -1;
  int preview_div = 4;         ///< first frame of every restart at this fraction of the resolution
  double full_res_frame_seconds = 0.0;

  // What the edits cost, counted (the tier tests read these).
  int geometry_builds = 0;
  int geometry_refits = 0;
  int restarts = 0;

  // Measurements.
  std::map<uint64_t, Clock::time_point> restart_started;  ///< epoch -> time of the edit
  std::vector<double> restart_latency_ms;
  uint64_t ui_frames = 0;
  Clock::time_point start_time = Clock::now();
  double load_ms = 0.0;

  // Background work.
  std::future<Result<LoadedScene>> loading;
  std::shared_ptr<LoadProgress> load_progress;
  std::string loading_path;
  std::string status;          ///< the last message of a save, load or refused edit: the panel column's first line
  /// The messages before it, oldest first, at most kEarlierMessages: a save that finishes while a load is said, or
  /// two refusals in one frame, are not lost to the next message.
  std::deque<std::string> earlier_messages;
  static constexpr size_t kEarlierMessages = 8;
  /// The one way a message reaches the status line (panels, loads, saves, scripts).
  void say(std::string message);
  /// An image being written on its own thread (save_current), until poll_saves takes its outcome.
  struct PendingSave {
    std::string path;
    std::future<std::optional<Error>> result;
  };
  std::vector<PendingSave> saves;
  std::vector<Error> save_errors;  ///< saves that failed: reported on stderr at exit, and by the exit code (2)

  /// Installs `scene` (finalized) and builds its geometry on this thread; with `threads` >= 0 also starts a render
  /// session (tests without rendering pass -1).
  void init(Scene scene, const RenderParams& params, const DisplaySettings& display, int threads);
  /// B's parameters: A's with the compare config's integrator, light sampling and sampler.
  RenderParams params_b() const;
  /// Pauses or resumes rendering (both sides in a compare).
  void set_paused(bool p);
  /// Gives the render to A or B in turn, every kCompareSliceSeconds of wall-clock time; call once per UI frame.
  void tick_compare();
  /// Takes a newly fetched B frame (its true relMSE).
  void note_frame_b();
  /// Takes a newly fetched frame: records its error history (reset with each epoch).
  void note_frame();
  /// Fetches the newest frame into `frame`, merged with the other ranks' samples under mpirun (`offload`), and
  /// notes it when it is new (note_frame). Never waits. The viewer's loop and the tests that drive it call this.
  bool fetch_frame();
  /// The same for B's side of a compare (note_frame_b); false without one.
  bool fetch_frame_b();
  /// True relMSE of the current frame against the reference (NaN without one or when the sizes differ); computed
  /// once per fetched frame by note_frame, not per UI frame.
  double true_rel_mse() const { return frame_rel_mse; }
  double frame_rel_mse = std::numeric_limits<double>::quiet_NaN();
  /// A full frame's relMSE against the reference; NaN for a preview, without a reference or at another size.
  double rel_mse_to_reference(const SessionFrame& f) const;

  /// Applies an edit: the one place that chooses and performs the restart tier. Returns the tier performed (none
  /// when the edit was rejected or changed nothing: an edit to the values already there, such as the camera reset
  /// at the home camera, keeps the samples).
  Tier apply(const Edit& edit);

  /// Starts loading a scene file in the background; the current scene stays live until it is ready.
  void start_load(const std::string& path);
  /// Applies a finished load, if any (a SceneEdit). Returns true if a new scene was installed.
  bool poll_load();
  /// Takes the saves that finished, in the order they were asked for: the status line says "saved PATH" or why
  /// not, and failures go to save_errors. With `wait`, first waits for all of them (at exit: no file half-written).
  void poll_saves(bool wait = false);
  /// Object under full-resolution pixel (x, y): its material, and the light it belongs to (or -1).
  struct PickResult {
    int material = -1;
    int light = -1;
  };
  PickResult pick(int x, int y) const;
  /// Selects what `pick` found: its material, and the light if it is one.
  bool select_at(int x, int y);
  /// Saves the current mean to `path` on a background thread (the status line says "saving PATH" until
  /// poll_saves sees it done).
  void save_current(const std::string& path);
  /// Writes the scene as shown (camera, edited materials and lights, meshes) as a version-1 JSON, atomically.
  std::optional<Error> save_scene(const std::string& path);
  std::string stats_json() const;
  /// The threads that rendered the frame shown (the session's count before its first frame; 0 without a session):
  /// what the Stats panel and stats_json report.
  int render_threads() const;

 private:
  /// Material `index` set to `m`, normalized; Tier::none when that is what it already was.
  Tier set_material(size_t index, const Material& m);
  void restart();
  Tier commit(Tier tier);
};

/// The q-quantile (0..1) of `v` by the nearest rank on the sorted values; 0 for an empty list. The Stats panel and
/// the stats JSON's restart_latency_ms both use it.
double percentile(std::vector<double> v, double q);

}  // namespace pt
