/// The headless path: render frames, report progress on a terminal, write the image, stats and error curve.
/// One process renders through a ProgressiveFilm (adaptive sampling included); several MPI ranks (src/dist) shard
/// the sample ranges of every pixel by frame and rank 0 sums their films.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "app/app.h"
#include "core/atomic_file.h"
#include "render/adaptive.h"
#include "render/convergence.h"
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

/// One --error-csv row: frame,spp,seconds,rmse,rel_mse,est_rel_mse; rmse and rel_mse empty without a reference,
/// est_rel_mse empty while unknown.
void append_error_row(std::ostringstream& csv, const RunSummary& run, double seconds, const Film& film,
                      const std::optional<Image>& reference) {
  char row[200];
  int n = std::snprintf(row, sizeof row, "%d,%d,%.6f,", run.frames, run.spp, seconds);
  if (reference) {
    ImageError e = compare_images(film.resolve(), *reference);
    n += std::snprintf(row + n, sizeof row - n, "%.9g,%.9g,", e.rmse, e.rel_mse);
  } else {
    n += std::snprintf(row + n, sizeof row - n, ",,");
  }
  double est = est_rel_mse(film);
  if (std::isfinite(est)) std::snprintf(row + n, sizeof row - n, "%.9g", est);
  csv << row << "\n";
}

/// What a render loop leaves for the outputs.
struct LoopResult {
  Film film;  ///< the whole image's film (on rank 0)
  double render_seconds = 0.0;
};

/// What both sharded loops keep: this rank's film and the combined one (on rank 0), this rank's work and the clock.
/// end_round() is every round's tail, finish() the end of the render.
struct ShardRun {
  const AppOptions& options;
  Cluster& cluster;
  RunSummary& run;
  Film film, total;
  RankWork mine;
  const bool progress;
  const int frames_total;  ///< 0: until another limit
  const Clock::time_point start = Clock::now();
  double render_seconds = 0.0;  ///< rank 0: rendering and combining the ranks' films
  bool summed = false;          ///< `total` holds the current round

  ShardRun(const AppOptions& o, Cluster& c, RunSummary& r)
      : options(o), cluster(c), run(r), film(o.render.width, o.render.height),
        progress(::isatty(STDERR_FILENO) && c.root()), frames_total(o.frames.value_or(0)) {}

  /// The tail of a round begun at t0: a CSV row when the round was combined, the progress line. Returns whether the
  /// ranks agree that the time limit is reached.
  bool end_round(Clock::time_point t0, std::ostringstream& error_csv, const std::optional<Image>& reference) {
    render_seconds += seconds_since(t0);
    if (summed && cluster.root()) append_error_row(error_csv, run, render_seconds, total, reference);
    if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), false);
    return options.time_limit && cluster.any(seconds_since(start) >= *options.time_limit);
  }

  /// The end: the films not yet combined, the counters and each rank's work reduced to rank 0, the final progress
  /// line, and the combined film's convergence figures (the adaptive ones are the adaptive loop's to add).
  LoopResult finish() {
    Clock::time_point t0 = Clock::now();
    if (!summed) cluster.sum_films(film, total);
    run.counters = cluster.sum_counters(run.counters);
    render_seconds += seconds_since(t0);
    run.per_rank = cluster.gather_work(mine);
    if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), true);
    if (cluster.root()) {
      run.convergence.est_rel_mse = est_rel_mse(total);
      run.convergence.spp = spp_summary(total);
    }
    return {std::move(total), render_seconds};
  }
};

/// Frames per pass over the tiles (ProgressiveFilm::frames_per_pass says why several), about kHeadlessPassSeconds
/// of them, or one when a CSV row is due every frame. The image is the same bit for bit.
int frames_per_pass(const AppOptions& options, const ProgressiveFilm& film, double frame_seconds, double elapsed) {
  constexpr int kAll = std::numeric_limits<int>::max();
  if (!options.error_csv.empty()) return 1;
  int frames_left = options.frames ? *options.frames - film.frames() : kAll;
  if (options.time_limit && frame_seconds > 0.0)
    frames_left = int(std::min(double(frames_left), std::max(1.0, (*options.time_limit - elapsed) / frame_seconds)));
  const int spp_left = options.max_spp ? *options.max_spp - film.spp() : kAll;
  return film.frames_per_pass(options.render.spp_per_frame, frame_seconds, kHeadlessPassSeconds, frames_left, spp_left);
}

/// One process: progressive frames through a ProgressiveFilm, ending at --frames, --max-spp, --time-limit, or when
/// adaptive sampling has stopped every pixel.
LoopResult render_single(const AppOptions& options, const RenderScene& rs, Renderer& renderer, RunSummary& run,
                         std::ostringstream& error_csv, const std::optional<Image>& reference) {
  const RenderParams& params = options.render;
  ProgressiveFilm film;
  film.reset(params.width, params.height);
  film.set_adaptive(options.adaptive);
  const bool progress = ::isatty(STDERR_FILENO);
  const int frames_total = options.frames.value_or(0);  // 0: until another limit
  const Clock::time_point start = Clock::now();
  double render_seconds = 0.0, frame_seconds = 0.0;
  while ((frames_total == 0 || film.frames() < frames_total) && !(options.max_spp && film.spp() >= *options.max_spp) &&
         !film.converged()) {
    const int frames = frames_per_pass(options, film, frame_seconds, seconds_since(start));
    RenderParams p = params;
    p.spp_per_frame = frames * params.spp_per_frame;
    if (options.max_spp) p.spp_per_frame = std::min(p.spp_per_frame, *options.max_spp - film.spp());
    Clock::time_point t0 = Clock::now();
    film.render_frame(renderer, rs, p, run.counters, nullptr, frames);
    const double pass_seconds = seconds_since(t0);
    render_seconds += pass_seconds;
    frame_seconds = pass_seconds / frames;
    run.frames = film.frames();
    run.spp = film.spp();
    if (!options.error_csv.empty()) append_error_row(error_csv, run, render_seconds, film.film(), reference);
    if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), false);
    if (options.time_limit && seconds_since(start) >= *options.time_limit) break;
  }
  if (progress) print_progress(run.frames, frames_total, run.spp, render_seconds, run.counters.rays(), true);
  run.convergence = summarize_convergence(film);
  run.per_rank = {RankWork{run.spp, render_seconds}};
  return {std::move(film.film()), render_seconds};
}

/// Several ranks: sample-range sharding (dist/cluster.h). In round k this rank renders global frame k * ranks +
/// rank, the frames of several rounds in one pass; `film` holds this rank's samples, the result all ranks' (on
/// rank 0). Adaptive sampling and --max-spp take render_sharded_adaptive.
LoopResult render_sharded(const AppOptions& options, const RenderScene& rs, Renderer& renderer, RunSummary& run,
                          std::ostringstream& error_csv, const std::optional<Image>& reference, Cluster& cluster) {
  const RenderParams& params = options.render;
  const int ranks = cluster.ranks();
  ShardRun s(options, cluster, run);
  const int frames_total = s.frames_total;  // 0: until the time limit
  // Rounds per pass: each rank renders its frames of kMaxFramesPerPass rounds in one pass over the tiles (as one
  // process does; ProgressiveFilm::frames_per_pass), unless a CSV row or a time-limit check is due every round.
  // The same on every rank: the number of end_round calls, which are collective, must agree.
  const int rounds_per_pass = options.error_csv.empty() && !options.time_limit ? kMaxFramesPerPass : 1;
  for (int round = 0; frames_total == 0 || int64_t(round) * ranks < frames_total; round += rounds_per_pass) {
    Clock::time_point t0 = Clock::now();
    std::vector<uint32_t> frames;
    for (int k = 0; k < rounds_per_pass; ++k) {
      const int64_t frame = shard_frame(round + k, cluster.rank(), ranks);
      if (frames_total == 0 || frame < frames_total) frames.push_back(uint32_t(frame));
    }
    if (!frames.empty()) {
      renderer.render_frames(rs, params, s.film, frames.data(), int(frames.size()), run.counters);
      s.mine.spp += int(frames.size()) * params.spp_per_frame;
      s.mine.seconds += seconds_since(t0);
    }
    run.frames = int(frames_after_rounds(round + rounds_per_pass, ranks, frames_total));
    run.spp = run.frames * params.spp_per_frame;
    s.summed = false;
    if (!options.error_csv.empty()) {  // the same on every rank (collective): a CSV row per round
      cluster.sum_films(s.film, s.total);
      s.summed = true;
    }
    if (s.end_round(t0, error_csv, reference)) break;
  }
  return s.finish();
}

/// Several ranks with adaptive sampling or --max-spp: every rank holds the combined film's state (each pixel's next
/// sample index `first`, the active mask, the sample level) and takes the single-process loop's steps (render_single)
/// in rounds of up to `ranks` x kMaxFramesPerPass of its frames, rank r rendering the r-th of `ranks` runs of
/// consecutive frames of the round in one pass: the samples first[p] + offset .. of every active pixel. A round
/// ends early at a convergence check, where rank 0 sums the films
/// (in a fixed order, dist/cluster.h) and tests convergence, and broadcasts the active mask: one decision, taken once,
/// so every rank continues with the same mask and stops in the same round. The samples are then those of one
/// process; only the order of their summation differs.
LoopResult render_sharded_adaptive(const AppOptions& options, const RenderScene& rs, Renderer& renderer,
                                   RunSummary& run, std::ostringstream& error_csv,
                                   const std::optional<Image>& reference, Cluster& cluster) {
  const RenderParams& params = options.render;
  const int ranks = cluster.ranks();
  const AdaptiveParams& adaptive = options.adaptive;
  ShardRun s(options, cluster, run);
  const size_t pixels = s.film.pixel_count();
  std::vector<uint32_t> first(pixels, 0);  // the combined film's `taken`
  std::vector<uint8_t> active(pixels, 1);
  size_t active_count = pixels;
  bool checked = false;
  int level = 0, frames = 0;
  int next_check = adaptive.enabled() ? effective_min_spp(adaptive) : std::numeric_limits<int>::max();
  const int frames_total = s.frames_total;
  auto more = [&](int lvl, int fr) {
    return (frames_total == 0 || fr < frames_total) && !(options.max_spp && lvl >= *options.max_spp);
  };
  // Up to kMaxFramesPerPass frames a rank a round, rendered in one pass (as render_sharded does), unless a CSV row
  // or a time-limit check is due every round. The same on every rank: the plan below must agree.
  const int frames_per_rank = options.error_csv.empty() && !options.time_limit ? kMaxFramesPerPass : 1;
  while (more(level, frames) && !(checked && active_count == 0)) {
    Clock::time_point t0 = Clock::now();
    // The single-process frames of this round: (sample offset, spp) each, ending at a check or a limit.
    std::vector<std::pair<int, int>> plan;
    int lvl = level;
    while (int(plan.size()) < ranks * frames_per_rank && more(lvl, frames + int(plan.size())) && lvl < next_check) {
      int spp = params.spp_per_frame;
      if (options.max_spp) spp = std::min(spp, *options.max_spp - lvl);
      plan.emplace_back(lvl - level, spp);
      lvl += spp;
    }
    // Rank r takes the r-th of `ranks` near-equal runs of consecutive frames: one range of samples, one pass.
    const size_t begin = plan.size() * size_t(cluster.rank()) / size_t(ranks);
    const size_t end = plan.size() * size_t(cluster.rank() + 1) / size_t(ranks);
    if (begin < end) {
      RenderParams p = params;
      p.spp_per_frame = 0;
      for (size_t i = begin; i < end; ++i) p.spp_per_frame += plan[i].second;
      renderer.render_range(rs, p, s.film, adaptive.enabled() ? active.data() : nullptr, first.data(),
                            uint32_t(plan[begin].first), run.counters);
      s.mine.spp += p.spp_per_frame;
      s.mine.seconds += seconds_since(t0);
    }
    for (size_t q = 0; q < pixels; ++q) first[q] += active[q] ? uint32_t(lvl - level) : 0u;
    level = lvl;
    frames += int(plan.size());
    run.frames = frames;
    run.spp = level;
    s.summed = false;
    if (level >= next_check || !options.error_csv.empty()) {
      cluster.sum_films(s.film, s.total);
      s.summed = true;
    }
    if (level >= next_check) {
      if (cluster.root()) compute_active_pixels(s.total, adaptive.noise_threshold, effective_min_spp(adaptive), active);
      cluster.broadcast(active);
      active_count = size_t(std::count(active.begin(), active.end(), uint8_t(1)));
      checked = true;
      next_check = level + kAdaptiveCheckInterval;
    }
    if (s.end_round(t0, error_csv, reference)) break;
  }
  LoopResult result = s.finish();
  if (cluster.root() && adaptive.enabled()) {
    if (checked) run.convergence.converged_fraction = 1.0 - double(active_count) / double(pixels);
    run.convergence.noise_threshold = adaptive.noise_threshold;
    run.convergence.min_spp = effective_min_spp(adaptive);
  }
  return result;
}

}  // namespace

int run_headless(const AppOptions& options, const Scene& scene, Cluster& cluster, double load_ms) {
  const RenderParams& params = options.render;
  RenderScene rs = make_render_scene(scene);
  for (const std::string& w : cluster.root() ? scene.warnings : std::vector<std::string>{})
    std::fprintf(stderr, "ptview: warning: %s\n", Error::one_line(w).c_str());

  std::optional<Image> reference;
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
    }
  }
  if (std::string err = cluster.first_error(reference_error); !err.empty()) return report_error(cluster, err);
  std::ostringstream error_csv;
  error_csv << "frame,spp,seconds,rmse,rel_mse,est_rel_mse\n";

  Renderer renderer(params.threads);
  RunSummary run;
  run.load_ms = load_ms;
  run.threads = renderer.thread_count();
  const bool sharded_adaptive = options.adaptive.enabled() || options.max_spp;
  LoopResult result =
      cluster.ranks() == 1 ? render_single(options, rs, renderer, run, error_csv, reference)
      : sharded_adaptive   ? render_sharded_adaptive(options, rs, renderer, run, error_csv, reference, cluster)
                           : render_sharded(options, rs, renderer, run, error_csv, reference, cluster);
  run.seconds = result.render_seconds;
  run.comm_ms = cluster.comm_ms();
  if (!cluster.root()) return 0;  // rank 0 writes every output
  const Film& film = result.film;

  int code = 0;
  if (auto err = save_image(options.out, film.resolve(), options.display)) {
    std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
    code = 2;
  } else if (!options.out_given) {
    std::printf("ptview: wrote %s (%d spp, %.2f s)\n", options.out.c_str(), run.spp, run.seconds);
  }
  for (auto [path, map] : {std::pair{&options.error_map, &rel_error_image}, std::pair{&options.spp_map, &spp_image}}) {
    if (path->empty()) continue;
    if (auto err = save_image(*path, map(film))) {
      std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
      code = 2;
    }
  }
  if (!options.error_csv.empty()) {
    if (auto err = write_file_atomic(options.error_csv, error_csv.str())) {
      std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
      code = 2;
    }
  }
  if (!options.stats_json.empty()) {
    if (auto err =
            write_file_atomic(options.stats_json, make_stats_json(options.render, scene, rs, run).dump(2) + "\n")) {
      std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
      code = 2;
    }
  }
  return code;
}

}  // namespace pt
