#pragma once
/// A progressive render that runs on its own driver thread and restarts when told: the engine behind the viewer.
/// Edits never block the caller: they store the new state, bump an epoch and cancel the frame in flight; the driver
/// notices at the next tile, drops the stale partial frame, clears the film and starts over. Only the destructor
/// joins the driver thread.
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "render/renderer.h"

namespace pt {

/// What the driver publishes after each completed frame.
struct SessionFrame {
  uint64_t epoch = 0;
  bool preview = false;     ///< the quick low-resolution first look at a new epoch (its samples are not kept)
  int frames = 0;           ///< full-resolution frames completed in this epoch
  int spp = 0;
  int width = 0, height = 0;
  double seconds = 0.0;     ///< render time in this epoch
  RenderCounters counters;  ///< of this epoch
  Image image;              ///< the current mean
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
  /// Every epoch first renders and publishes one frame at 1/divisor resolution, so an edit shows within a few
  /// milliseconds even when a full frame takes much longer (1: off).
  void set_preview_divisor(int divisor) { preview_div_ = std::max(1, divisor); }
  uint64_t epoch() const { return epoch_.load(); }
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
  int thread_count_ = 1;

  std::mutex publish_mutex_;
  SessionFrame published_;
  std::jthread driver_;
};

}  // namespace pt
