#pragma once
/// Adaptive sampling (as Cycles does it: intern/cycles/kernel/film/adaptive_sampling.h and
/// integrator/adaptive_sampling.cpp): after a minimum number of samples, every 16 samples the pixels whose relative
/// standard error (pixel_rel_error, render/convergence.h) is below the noise threshold stop receiving samples.
/// The unconverged region is dilated by one pixel first (a pixel keeps sampling while any of its 8 neighbours
/// does), because the per-pixel estimate has one degree of freedom and can be small by chance, most harmfully
/// at edges.
///
/// The active set is recomputed from the film at every check, never carried over, so changing the threshold
/// needs no restart: lowering it makes stopped pixels active again at once, and they continue from their own
/// next sample index (Film::taken), which keeps every pixel's samples a prefix of its sequence. Because each
/// decision depends only on the film, which is bit-identical for any thread count, so are adaptive runs.
#include <cstdint>
#include <limits>
#include <vector>

#include "render/renderer.h"

namespace pt {

struct AdaptiveParams {
  double noise_threshold = 0.0;  ///< 0: off (every pixel gets every sample)
  int min_spp = 0;               ///< 0: automatic (auto_min_spp)
  bool enabled() const { return noise_threshold > 0.0; }
};

inline constexpr int kAdaptiveCheckInterval = 16;
inline constexpr int kMaxFramesPerPass = 16;
/// How long a pass lasts. Headless: no one looks at the film between frames, and a quarter second keeps the progress
/// line moving and --time-limit overrun by no more than a frame (the throughput bench measures the same loop).
/// Interactive (the viewer's session and the ranks that render for it): a pass of a display update still shows the
/// image converge smoothly, and a restart cancels it at the next tile all the same.
inline constexpr double kHeadlessPassSeconds = 0.25;
inline constexpr double kInteractivePassSeconds = 1.0 / 30.0;

/// The frames of `frame_seconds` each that fill a pass of about `pass_seconds`: at least 1 (also while the frame
/// time is unknown, <= 0), at most kMaxFramesPerPass. ProgressiveFilm::frames_per_pass says why a pass takes
/// several frames; every loop that renders passes (headless, the viewer's session, the offload's ranks, the
/// throughput bench) sizes them here.
int frames_for_pass_time(double frame_seconds, double pass_seconds);

/// Cycles' automatic minimum: ceil(16 / T^0.3), at least 4 (T = 0.1 -> 32, 0.01 -> 64, 0.001 -> 128), rounded up
/// to an even number so that both halves of the estimator hold as many samples.
int auto_min_spp(double noise_threshold);
int effective_min_spp(const AdaptiveParams& params);

/// active[p] = 1 iff pixel p has fewer than min_spp samples or some pixel of its 3x3 neighbourhood has
/// pixel_rel_error >= threshold (or an unknown error). Returns the number of active pixels.
size_t compute_active_pixels(const Film& film, double threshold, int min_spp, std::vector<uint8_t>& active);

/// One progressive render: the film, and which pixels still sample. The loop body shared by the headless path
/// and the session; with adaptive sampling off it is plain progressive rendering.
class ProgressiveFilm {
 public:
  void reset(int width, int height);
  /// Takes effect at once, without a restart: the active set is recomputed if the minimum is reached.
  void set_adaptive(const AdaptiveParams& params);
  const AdaptiveParams& adaptive() const { return adaptive_; }

  /// Adds params.spp_per_frame samples to every active pixel (each continues from its own sample index), then
  /// runs the convergence check when one is due. False if cancelled (the film holds a partial, still consistent,
  /// frame: every pixel's samples remain a prefix of its sequence).
  ///
  /// `frames` > 1 renders that many frames in one pass over the tiles: params.spp_per_frame is then the samples of
  /// all of them. The film is the same bit for bit as frame by frame (each pixel takes the same samples in the same
  /// order), provided the pass ends where a frame would run the convergence check: see frames_to_check().
  bool render_frame(Renderer& renderer, const RenderScene& scene, const RenderParams& params,
                    RenderCounters& counters, const std::atomic<bool>* cancel = nullptr, int frames = 1);
  /// The frames of `spp_per_frame` samples up to and including the one after which the next convergence check runs
  /// (a large number when adaptive sampling is off): the most one render_frame call may stand for.
  int frames_to_check(int spp_per_frame) const;
  /// The frames the next pass should render: as many as take about `pass_seconds` at `frame_seconds` a frame (1
  /// while that is unknown, <= 0), at most kMaxFramesPerPass, `frames_left`, the frames that hold `spp_left`
  /// samples, and frames_to_check(). Why several: a pass renders each pixel's samples one after the other, so the
  /// part of the scene a tile sees stays in cache, where 1-sample frames stream the whole tree and mesh through the
  /// cache once a frame (the 69k-triangle bunny at 256x256: about 2.5 ms a frame, 15% of its time;
  /// docs/BENCHMARKS.md, twelfth round). Cycles renders several samples per pass for the same reason
  /// (intern/cycles/integrator/render_scheduler.cpp).
  int frames_per_pass(int spp_per_frame, double frame_seconds, double pass_seconds,
                      int frames_left = std::numeric_limits<int>::max(),
                      int spp_left = std::numeric_limits<int>::max()) const;

  const Film& film() const { return film_; }
  Film& film() { return film_; }
  int frames() const { return frames_; }
  /// Samples per pixel of a pixel that never stopped (the maximum over pixels).
  int spp() const { return level_; }
  /// Adaptive sampling is on, past its minimum, and no pixel is active.
  bool converged() const { return adaptive_.enabled() && checked_ && active_count_ == 0; }
  /// Fraction of pixels that currently receive no samples (0 before the first check or when adaptive is off).
  double converged_fraction() const;
  const std::vector<uint8_t>& active() const { return active_; }

 private:
  void check();

  Film film_;
  AdaptiveParams adaptive_;
  std::vector<uint8_t> active_;
  size_t active_count_ = 0;
  bool checked_ = false;  ///< active_ comes from a convergence check (else every pixel is active)
  int frames_ = 0;
  int level_ = 0;
  int next_check_ = 0;
};

}  // namespace pt
