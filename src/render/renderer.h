#pragma once
/// Progressive rendering: one frame adds `spp_per_frame` samples to every pixel of a Film, split into tiles over a
/// WorkerPool. Each pixel sample draws its random numbers from (seed, pixel, sample index) alone, so the image is
/// bit-identical for any thread count. Used by the headless path and the viewer alike.
#include <atomic>
#include <memory>

#include "render/camera.h"
#include "render/film.h"
#include "render/integrator.h"
#include "render/worker_pool.h"

namespace pt {

inline constexpr int kTileSize = 16;

class Renderer {
 public:
  explicit Renderer(int threads = 0) : pool_(std::make_unique<WorkerPool>(threads)) {}
  int thread_count() const { return pool_->thread_count(); }

  /// Adds one frame of samples (frame index `frame` fixes the sample indices) to `film`, which must be sized
  /// params.width x params.height. If `cancel` is given and becomes true, stops at the next tile and returns
  /// false (the film then holds a partial frame and should be cleared).
  bool render_frame(const RenderScene& scene, const RenderParams& params, Film& film, uint32_t frame,
                    RenderCounters& counters, const std::atomic<bool>* cancel = nullptr);
  /// The frames frames[0] .. frames[count - 1] in one pass over the tiles: each pixel takes their samples one
  /// after the other, in that order, before the next pixel (why: ProgressiveFilm::frames_per_pass). The film is
  /// that of render_frame called for each frame in turn, bit for bit.
  bool render_frames(const RenderScene& scene, const RenderParams& params, Film& film, const uint32_t* frames,
                     int count, RenderCounters& counters, const std::atomic<bool>* cancel = nullptr);
  /// Adds `spp_per_frame` samples to each pixel with active[p] != 0 (every pixel if `active` is null), each pixel
  /// continuing from its own next sample index film.taken[p]: adaptive sampling (render/adaptive.h). For a film
  /// that only ever received whole passes or frames from frame 0 this equals render_frame with the next frame.
  bool render_pass(const RenderScene& scene, const RenderParams& params, Film& film, const uint8_t* active,
                   RenderCounters& counters, const std::atomic<bool>* cancel = nullptr);
  /// Adds samples first[p] + offset .. first[p] + offset + spp_per_frame - 1 of each active pixel (every pixel if
  /// `active` is null) to `film`, whose own counts play no part: one rank's share of a pass whose pixels continue
  /// from the sample indices `first` of the combined film (adaptive sampling across MPI ranks, app/headless.cpp).
  /// False if cancelled (as render_frame).
  bool render_range(const RenderScene& scene, const RenderParams& params, Film& film, const uint8_t* active,
                    const uint32_t* first, uint32_t offset, RenderCounters& counters,
                    const std::atomic<bool>* cancel = nullptr);

 private:
  std::unique_ptr<WorkerPool> pool_;
};

/// Renders one sample batch of a single pixel; exposed for tests.
void render_pixel(const RenderScene& scene, const RenderParams& params, const CameraRig& rig, const SamplerKeys& keys,
                  int x, int y, uint32_t first_sample, Film& film, RenderCounters& counters);

}  // namespace pt
