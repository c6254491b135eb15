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

int run_headless(const AppOptions& options, const Scene& scene, Cluster& cluster) {
  const RenderParams& params = options.render;
  RenderScene rs = make_render_scene(scene);
  for (const std::string& w : cluster.root() ? scene.warnings : std::vector<std::string>{})
    std::fprintf(stderr, "ptview: warning: %s\n", Error::one_line(w).c_str());

  std::optional<Image> reference;
  std::ostringstream error_csv;
  std::string reference_error;  // only rank 0 reads the reference
  if (!options.reference.empty() && cluster.root()) {
    Result<Image> ref = load_image(options.reference);
    if (!ref) {
      reference_error = ref.error();
    } else if (ref->width != params.width || ref->height != params.height) {
      reference_error = options.reference + ": reference is " + std::to_string(ref->width) + "x" +
                        std::to_string(ref->height) + " but the render is " + std::to_string(params.width) + "x" +
                        std::to_string(params.height);
    } else {
      reference = std::move(*ref);
      error_csv << "frame,spp,seconds,rmse,rel_mse\n";
    }
  }
  if (std::string err = cluster.first_error(reference_error); !err.empty()) return report_error(cluster, err);

  // Sample-range sharding (dist/cluster.h): in round k this rank renders global frame k * ranks + rank; with one
  // process that is frame k. `film` holds this rank's samples, `total` all ranks' (on rank 0).
  const int ranks = cluster.ranks();
  Renderer renderer(params.threads);
  Film film(params.width, params.height), total;
  RunSummary run;
  RankWork mine;
  run.threads = renderer.thread_count();
  const bool progress = ::isatty(STDERR_FILENO) && cluster.root();
  const int frames_total = options.frames.value_or(0);  // 0: until the time limit
  const Clock::time_point start = Clock::now();
  double render_seconds = 0.0;  // rank 0: rendering and combining the ranks' films
  bool summed = false;          // `total` holds the current round
  for (int round = 0; frames_total == 0 || int64_t(round) * ranks < frames_total; ++round) {
    Clock::time_point t0 = Clock::now();
    const int64_t frame = shard_frame(round, cluster.rank(), ranks);
    if (frames_total == 0 || frame < frames_total) {
      renderer.render_frame(rs, params, film, uint32_t(frame), run.counters);
      mine.spp += params.spp_per_frame;
      mine.seconds += seconds_since(t0);
    }
    run.frames = int(frames_after_rounds(round + 1, ranks, frames_total));
    run.spp = run.frames * params.spp_per_frame;
    summed = false;
    if (!options.error_csv.empty() && ranks > 1) {  // the same on every rank (collective): a CSV row per round
      cluster.sum_films(film, total);
      summed = true;
    }
    render_seconds += seconds_since(t0);
    if (reference && (ranks == 1 || summed)) {
      ImageError e = compare_images((ranks > 1 ? total : film).resolve(), *reference);
      char row[160];
      std::snprintf(row, sizeof row, "%d,%d,%.6f,%.9g,%.9g\n", run.frames, run.spp, render_seconds, e.rmse, e.rel_mse);
      error_csv << row;
    }
    if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), false);
    if (options.time_limit && cluster.any(seconds_since(start) >= *options.time_limit)) break;
  }
  if (ranks > 1) {
    Clock::time_point t0 = Clock::now();
    if (!summed) cluster.sum_films(film, total);
    run.counters = cluster.sum_counters(run.counters);
    render_seconds += seconds_since(t0);
  }
  run.seconds = render_seconds;
  run.per_rank = cluster.gather_work(mine);
  run.comm_ms = cluster.comm_ms();
  if (!cluster.root()) return 0;  // rank 0 writes every output
  if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), true);
  const Film& image = ranks > 1 ? total : film;

  int code = 0;
  if (auto err = save_image(options.out, image.resolve(), options.display)) {
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
