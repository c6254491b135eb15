#include "render/renderer.h"

#include <mutex>

namespace pt {

void render_pixel(const RenderScene& scene, const RenderParams& params, const CameraRig& rig, int x, int y,
                  uint32_t first_sample, Film& film, RenderCounters& counters) {
  const size_t pixel = size_t(y) * size_t(params.width) + size_t(x);
  for (int s = 0; s < params.spp_per_frame; ++s) {
    PixelSampler sampler = PixelSampler::start(params.seed, pixel, uint64_t(first_sample) + uint64_t(s), params.sampler);
    Ray ray = generate_camera_ray(rig, x, y, sampler.next2d());
    vec3 L = trace_path(scene, params, ray, sampler, counters);
    ++counters.samples;
    if (!is_finite(L) || L.x < 0.0f || L.y < 0.0f || L.z < 0.0f) {
      ++counters.nonfinite_samples;  // dropped, counted, never averaged in
      continue;
    }
    film.add(pixel, L);
  }
}

bool Renderer::render_frame(const RenderScene& scene, const RenderParams& params, Film& film, uint32_t frame,
                            RenderCounters& counters, const std::atomic<bool>* cancel) {
  const CameraRig rig = make_camera_rig(scene.camera, params.width, params.height);
  const int tiles_x = (params.width + kTileSize - 1) / kTileSize;
  const int tiles_y = (params.height + kTileSize - 1) / kTileSize;
  const uint32_t first_sample = frame * uint32_t(params.spp_per_frame);
  std::mutex counters_mutex;
  std::atomic<bool> cancelled{false};
  pool_->parallel_for(uint32_t(tiles_x * tiles_y), [&](uint32_t tile, int) {
    if (cancel && cancel->load(std::memory_order_relaxed)) {
      cancelled = true;
      return;
    }
    RenderCounters local;
    int tx = int(tile) % tiles_x, ty = int(tile) / tiles_x;
    int x1 = std::min(params.width, (tx + 1) * kTileSize), y1 = std::min(params.height, (ty + 1) * kTileSize);
    for (int y = ty * kTileSize; y < y1; ++y)
      for (int x = tx * kTileSize; x < x1; ++x) render_pixel(scene, params, rig, x, y, first_sample, film, local);
    std::lock_guard lock(counters_mutex);
    counters += local;
  });
  return !cancelled;
}

}  // namespace pt
