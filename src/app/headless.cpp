/// The headless path: render frames, report progress on a terminal, write the image, stats and error curve.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <sstream>

#include "app/app.h"
#include "core/atomic_file.h"
#include "render/renderer.h"

namespace pt {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void print_progress(int frame, int frames_total, int spp, double seconds, uint64_t rays, bool finished) {
  double sps = seconds > 0 ? spp / seconds : 0.0;
  double mrays = seconds > 0 ? double(rays) / seconds * 1e-6 : 0.0;
  char eta[32] = "";
  if (frames_total > 0 && frame > 0 && !finished)
    std::snprintf(eta, sizeof eta, "  ETA %.1fs", seconds / frame * (frames_total - frame));
  char total[24] = "";
  if (frames_total > 0) std::snprintf(total, sizeof total, "/%d", frames_total);
  std::fprintf(stderr, "\rframe %d%s  spp %d  %.2f spp/s  %.2f Mrays/s  %.1fs%s%s", frame, total, spp, sps, mrays,
               seconds, eta, finished ? "\n" : "   ");
  std::fflush(stderr);
}

}  // namespace

int run_headless(const AppOptions& options, const Scene& scene, double load_ms) {
  const RenderParams& params = options.render;
  RenderScene rs = make_render_scene(scene);
  for (const std::string& w : scene.warnings)
    std::fprintf(stderr, "ptview: warning: %s\n", Error::one_line(w).c_str());

  std::optional<Image> reference;
  std::ostringstream error_csv;
  if (!options.reference.empty()) {
    Result<Image> ref = load_image(options.reference);
    if (!ref) {
      std::fprintf(stderr, "ptview: error: %s\n", ref.error().c_str());
      return 2;
    }
    if (ref->width != params.width || ref->height != params.height) {
      std::fprintf(stderr, "ptview: error: %s: reference is %dx%d but the render is %dx%d\n",
                   options.reference.c_str(), ref->width, ref->height, params.width, params.height);
      return 2;
    }
    reference = std::move(*ref);
    error_csv << "frame,spp,seconds,rmse,rel_mse\n";
  }

  Renderer renderer(params.threads);
  Film film(params.width, params.height);
  RunSummary run;
  run.load_ms = load_ms;
  run.threads = renderer.thread_count();
  const bool progress = ::isatty(STDERR_FILENO);
  const int frames_total = options.frames.value_or(0);  // 0: until the time limit
  const Clock::time_point start = Clock::now();
  double render_seconds = 0.0;
  for (int frame = 0; frames_total == 0 || frame < frames_total; ++frame) {
    Clock::time_point t0 = Clock::now();
    renderer.render_frame(rs, params, film, uint32_t(frame), run.counters);
    render_seconds += seconds_since(t0);
    run.frames = frame + 1;
    run.spp = run.frames * params.spp_per_frame;
    if (reference) {
      ImageError e = compare_images(film.resolve(), *reference);
      char row[160];
      std::snprintf(row, sizeof row, "%d,%d,%.6f,%.9g,%.9g\n", run.frames, run.spp, render_seconds, e.rmse, e.rel_mse);
      error_csv << row;
    }
    if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), false);
    if (options.time_limit && seconds_since(start) >= *options.time_limit) break;
  }
  run.seconds = render_seconds;
  if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), true);

  int code = 0;
  if (auto err = save_image(options.out, film.resolve(), options.display)) {
    std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
    code = 2;
  } else if (!options.out_given) {
    std::printf("ptview: wrote %s (%d spp, %.2f s)\n", options.out.c_str(), run.spp, run.seconds);
  }
  if (!options.error_csv.empty()) {
    if (auto err = write_file_atomic(options.error_csv, error_csv.str())) {
      std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
      code = 2;
    }
  }
  if (!options.stats_json.empty()) {
    if (auto err = write_file_atomic(options.stats_json, make_stats_json(options, scene, rs, run))) {
      std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
      code = 2;
    }
  }
  return code;
}

}  // namespace pt
