#include "render/adaptive.h"

#include <algorithm>
#include <cmath>

#include "render/convergence.h"

namespace pt {

int auto_min_spp(double t) {
  int m = std::max(4, int(std::ceil(16.0 / std::pow(t, 0.3))));
  return (m + 1) / 2 * 2;
}

int effective_min_spp(const AdaptiveParams& p) { return p.min_spp > 0 ? p.min_spp : auto_min_spp(p.noise_threshold); }

size_t compute_active_pixels(const Film& film, double threshold, int min_spp, std::vector<uint8_t>& active) {
  const int w = film.width, h = film.height;
  std::vector<uint8_t> bad(film.pixel_count());
  for (size_t p = 0; p < bad.size(); ++p)
    bad[p] = film.taken[p] < uint32_t(min_spp) || !(pixel_rel_error(film, p) < threshold);
  // Dilate with a 3x3 box, separably: rows, then columns.
  std::vector<uint8_t> rows(bad.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t p = size_t(y) * w + x;
      rows[p] = bad[p] | (x > 0 ? bad[p - 1] : 0) | (x + 1 < w ? bad[p + 1] : 0);
    }
  active.assign(bad.size(), 0);
  size_t n = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t p = size_t(y) * w + x;
      active[p] = rows[p] | (y > 0 ? rows[p - w] : 0) | (y + 1 < h ? rows[p + w] : 0);
      n += active[p];
    }
  return n;
}

void ProgressiveFilm::reset(int width, int height) {
  film_.reset(width, height);
  active_.assign(film_.pixel_count(), 1);
  active_count_ = active_.size();
  checked_ = false;
  frames_ = 0;
  level_ = 0;
  next_check_ = 0;
}

void ProgressiveFilm::set_adaptive(const AdaptiveParams& params) {
  adaptive_ = params;
  if (!adaptive_.enabled()) {
    active_.assign(film_.pixel_count(), 1);
    active_count_ = active_.size();
    checked_ = false;
    return;
  }
  next_check_ = effective_min_spp(adaptive_);
  if (level_ >= next_check_) check();
  else {
    active_.assign(film_.pixel_count(), 1);
    active_count_ = active_.size();
    checked_ = false;
  }
}

void ProgressiveFilm::check() {
  active_count_ = compute_active_pixels(film_, adaptive_.noise_threshold, effective_min_spp(adaptive_), active_);
  checked_ = true;
  next_check_ = level_ + kAdaptiveCheckInterval;
}

bool ProgressiveFilm::render_frame(Renderer& renderer, const RenderScene& scene, const RenderParams& params,
                                   RenderCounters& counters, const std::atomic<bool>* cancel, int frames) {
  const bool adaptive = adaptive_.enabled();
  if (adaptive && checked_ && active_count_ == 0) return true;  // converged: nothing to add
  bool done = renderer.render_pass(scene, params, film_, adaptive ? active_.data() : nullptr, counters, cancel);
  if (!done) return false;
  frames_ += frames;
  level_ += params.spp_per_frame;
  if (adaptive && level_ >= next_check_) check();
  return true;
}

int ProgressiveFilm::frames_to_check(int spp_per_frame) const {
  if (!adaptive_.enabled()) return std::numeric_limits<int>::max();
  return std::max(1, (next_check_ - level_ + spp_per_frame - 1) / spp_per_frame);  // level_ < next_check_ here
}

int frames_for_pass_time(double frame_seconds, double pass_seconds) {
  if (!(frame_seconds > 0.0)) return 1;
  return std::max(1, int(std::min(double(kMaxFramesPerPass), pass_seconds / frame_seconds)));
}

int ProgressiveFilm::frames_per_pass(int spp_per_frame, double frame_seconds, double pass_seconds, int frames_left,
                                     int spp_left) const {
  const double n = std::min({double(frames_for_pass_time(frame_seconds, pass_seconds)), double(frames_left),
                             std::ceil(double(spp_left) / spp_per_frame), double(frames_to_check(spp_per_frame))});
  return std::max(1, int(n));
}

double ProgressiveFilm::converged_fraction() const {
  if (!adaptive_.enabled() || !checked_ || active_.empty()) return 0.0;
  return 1.0 - double(active_count_) / double(active_.size());
}

}  // namespace pt
