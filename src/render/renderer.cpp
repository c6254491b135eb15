#include "render/renderer.h"

#include <mutex>

namespace pt {

void render_pixel(const RenderScene& scene, const RenderParams& params, const CameraRig& rig, const SamplerKeys& keys,
                  int x, int y, uint32_t first_sample, Film& film, RenderCounters& counters) {
  const size_t pixel = size_t(y) * size_t(params.width) + size_t(x);
  for (int s = 0; s < params.spp_per_frame; ++s) {
    const uint64_t index = uint64_t(first_sample) + uint64_t(s);
    PixelSampler sampler = PixelSampler::start(keys, pixel, index, params.sampler);
    Ray ray = generate_camera_ray(rig, x, y, sampler.next2d());
    vec3 L = trace_path(scene, params, ray, sampler, counters);
    ++counters.samples;
    film.note_taken(pixel);
    if (!is_finite(L) || L.x < 0.0f || L.y < 0.0f || L.z < 0.0f) {
      ++counters.nonfinite_samples;  // dropped, counted, never averaged in
      continue;
    }
    film.add(pixel, L, index);
  }
}

namespace {

/// Runs render(x, y) for every pixel, tile by tile over the pool; false if cancelled.
template <class F>
bool for_each_tile(WorkerPool& pool, int width, int height, RenderCounters& counters,
                   const std::atomic<bool>* cancel, F&& render) {
  const int tiles_x = (width + kTileSize - 1) / kTileSize;
  const int tiles_y = (height + kTileSize - 1) / kTileSize;
  std::mutex counters_mutex;
  std::atomic<bool> cancelled{false};
  pool.parallel_for(uint32_t(tiles_x * tiles_y), [&](uint32_t tile, int) {
    if (cancel && cancel->load(std::memory_order_relaxed)) {
      cancelled = true;
      return;
    }
    RenderCounters local;
    int tx = int(tile) % tiles_x, ty = int(tile) / tiles_x;
    int x1 = std::min(width, (tx + 1) * kTileSize), y1 = std::min(height, (ty + 1) * kTileSize);
    for (int y = ty * kTileSize; y < y1; ++y)
      for (int x = tx * kTileSize; x < x1; ++x) render(x, y, local);
    std::lock_guard lock(counters_mutex);
    counters += local;
  });
  return !cancelled;
}

}  // namespace

bool Renderer::render_frame(const RenderScene& scene, const RenderParams& params, Film& film, uint32_t frame,
                            RenderCounters& counters, const std::atomic<bool>* cancel) {
  return render_frames(scene, params, film, &frame, 1, counters, cancel);
}

bool Renderer::render_frames(const RenderScene& scene, const RenderParams& params, Film& film, const uint32_t* frames,
                             int count, RenderCounters& counters, const std::atomic<bool>* cancel) {
  const CameraRig rig = make_camera_rig(scene.camera, params.width, params.height);
  const SamplerKeys keys(params.seed);
  return for_each_tile(*pool_, params.width, params.height, counters, cancel, [&](int x, int y, RenderCounters& c) {
    for (int k = 0; k < count; ++k)
      render_pixel(scene, params, rig, keys, x, y, frames[k] * uint32_t(params.spp_per_frame), film, c);
  });
}

bool Renderer::render_pass(const RenderScene& scene, const RenderParams& params, Film& film, const uint8_t* active,
                           RenderCounters& counters, const std::atomic<bool>* cancel) {
  const CameraRig rig = make_camera_rig(scene.camera, params.width, params.height);
  const SamplerKeys keys(params.seed);
  return for_each_tile(*pool_, params.width, params.height, counters, cancel, [&](int x, int y, RenderCounters& c) {
    const size_t p = size_t(y) * size_t(params.width) + size_t(x);
    if (!active || active[p]) render_pixel(scene, params, rig, keys, x, y, film.taken[p], film, c);
  });
}

bool Renderer::render_range(const RenderScene& scene, const RenderParams& params, Film& film, const uint8_t* active,
                            const uint32_t* first, uint32_t offset, RenderCounters& counters,
                            const std::atomic<bool>* cancel) {
  const CameraRig rig = make_camera_rig(scene.camera, params.width, params.height);
  const SamplerKeys keys(params.seed);
  return for_each_tile(*pool_, params.width, params.height, counters, cancel, [&](int x, int y, RenderCounters& c) {
    const size_t p = size_t(y) * size_t(params.width) + size_t(x);
    if (!active || active[p]) render_pixel(scene, params, rig, keys, x, y, first[p] + offset, film, c);
  });
}

}  // namespace pt
