#pragma once
/// A progressive render that runs on its own driver thread and restarts when told: the engine behind the viewer.
/// Edits never block the caller: they store the new state, bump an epoch and cancel the frame in flight; the driver
/// notices at the next tile, drops the stale partial frame, clears the film and starts over. Only the destructor
/// joins the driver thread.
#include <atomic>
#include <condition_variable>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>

#include "render/adaptive.h"
#include "render/convergence.h"
#include "render/renderer.h"

namespace pt {

/// What the driver publishes after each completed frame.
struct SessionFrame {
  uint64_t epoch = 0;
  bool preview = false;     ///< the quick low-resolution first look at a new epoch (its samples are not kept)
  int frames = 0;           ///< full-resolution frames completed in this epoch
  uint64_t revision = 0;    ///< bumped by every publication (a republished frame has the same epoch and frames)
  int spp = 0;
  int width = 0, height = 0;
  double seconds = 0.0;     ///< render time in this epoch
  int threads = 0;          ///< the worker threads rendering this epoch (RenderParams::threads, 0 made concrete)
  RenderCounters counters;  ///< of this epoch
  Image image;              ///< the current mean
  // Convergence (render/convergence.h, render/adaptive.h); spp above is the maximum over pixels.
  double est_rel_mse = 0.0;         ///< NaN until both halves of the estimator hold samples
  double converged_fraction = 0.0;  ///< pixels adaptive sampling has stopped (0 when it is off)
  bool converged = false;           ///< adaptive sampling is on and every pixel has stopped: the session idles
  SppSummary spp_stats;
  Image rel_error;  ///< per-pixel relative standard error; only with set_publish_maps(true), else empty
  Image spp_map;    ///< samples per pixel; only with set_publish_maps(true), else empty
  std::vector<uint32_t> count;  ///< finite samples per pixel (Film::count); only with set_publish_counts(true)
  /// LightSampling::automatic's choice for the frame's scene and camera (RenderScene::auto_first_spread and
  /// auto_pilot_gain); NaN in a preview whose pilot has not run yet.
  float auto_first_spread = std::numeric_limits<float>::quiet_NaN();
  float auto_pilot_gain = std::numeric_limits<float>::quiet_NaN();
};

class RenderSession {
 public:
  explicit RenderSession(int threads = 0);
  ~RenderSession();
  RenderSession(const RenderSession&) = delete;
  RenderSession& operator=(const RenderSession&) = delete;

  /// Starts (or restarts) rendering `scene` with `params`. Returns the new epoch.
  uint64_t restart(std::shared_ptr<const RenderScene> scene, const RenderParams& params);
  /// Pausing keeps the accumulated image; resuming continues the same epoch.
  void set_paused(bool paused);
  bool paused() const { return paused_.load(); }
  /// Stop after this many samples per pixel (0: never).
  void set_target_spp(int spp);
  int target_spp() const { return target_spp_.load(); }
  /// Adaptive sampling on/off and its threshold, without a restart: the stopped set is re-evaluated at once
  /// (lowering the threshold resumes stopped pixels; a converged session starts rendering again).
  void set_adaptive(const AdaptiveParams& adaptive);
  /// Also publish the per-pixel error and spp maps with every frame (costs a pass over the film).
  /// Turning it on republishes the current frame with its maps at once, even when rendering has stopped (paused,
  /// target spp reached, converged), so a display mode that shows them never waits for a new frame.
  void set_publish_maps(bool on);
  /// Also publish every full frame's per-pixel sample counts (the viewer offload merges other ranks' sums).
  void set_publish_counts(bool on) { publish_counts_ = on; }
  /// Every epoch first renders and publishes one frame at 1/divisor resolution, so an edit shows within a few
  /// milliseconds even when a full frame takes much longer (1: off).
  void set_preview_divisor(int divisor) { preview_div_ = std::max(1, divisor); }
  uint64_t epoch() const { return epoch_.load(); }
  /// The threads the session was made with; an epoch renders with its RenderParams::threads (SessionFrame::threads).
  int thread_count() const { return thread_count_; }

  /// Copies the latest published frame into `out` if it is newer than `out` (by epoch and frame count).
  /// Cheap when nothing changed; never waits for rendering.
  bool fetch(SessionFrame& out);

 private:
  void drive(std::stop_token stop);

  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::shared_ptr<const RenderScene> scene_;
  RenderParams params_;
  std::atomic<uint64_t> epoch_{0};
  std::atomic<bool> cancel_{false};
  std::atomic<bool> paused_{false};
  std::atomic<int> target_spp_{0};
  std::atomic<int> preview_div_{1};
  std::atomic<bool> publish_maps_{false};
  std::atomic<bool> publish_counts_{false};
  std::atomic<bool> converged_{false};  ///< of the current epoch, written by the driver
  AdaptiveParams adaptive_;             ///< guarded by mutex_
  bool adaptive_changed_ = false;       ///< guarded by mutex_
  bool republish_ = false;              ///< guarded by mutex_: publish the current film again (with maps)
  int thread_count_ = 1;

  std::mutex publish_mutex_;
  SessionFrame published_;
  std::jthread driver_;
};

}  // namespace pt
