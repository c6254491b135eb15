#include "render/session.h"

#include <chrono>

#include "render/auto_light_sampling.h"

namespace pt {

RenderSession::RenderSession(int threads) {
  // The renderer (and its worker pool) lives on the driver thread; only its size is needed here.
  thread_count_ = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
  driver_ = std::jthread([this](std::stop_token st) { drive(st); });
}

RenderSession::~RenderSession() {
  {
    // Under the lock, like restart(): otherwise the driver, having just checked for a stop while taking up a new
    // epoch, could reset cancel_ after this and render a whole frame before it notices the stop.
    std::lock_guard lock(mutex_);
    driver_.request_stop();
    cancel_ = true;
  }
  wake_.notify_all();
}

uint64_t RenderSession::restart(std::shared_ptr<const RenderScene> scene, const RenderParams& params) {
  uint64_t e;
  {
    std::lock_guard lock(mutex_);
    scene_ = std::move(scene);
    params_ = params;
    e = ++epoch_;
    cancel_ = true;
  }
  wake_.notify_all();
  return e;
}

void RenderSession::set_paused(bool paused) {
  paused_ = paused;
  wake_.notify_all();
}

void RenderSession::set_adaptive(const AdaptiveParams& adaptive) {
  {
    std::lock_guard lock(mutex_);
    adaptive_ = adaptive;
    adaptive_changed_ = true;
  }
  wake_.notify_all();
}

void RenderSession::set_publish_maps(bool on) {
  {
    std::lock_guard lock(mutex_);
    publish_maps_ = on;
    republish_ = republish_ || on;
  }
  wake_.notify_all();
}

void RenderSession::set_target_spp(int spp) {
  {
    // Under the mutex, like every other change the driver waits on: a store between the driver's check of the
    // predicate and its sleep would otherwise lose the wake-up (raising the target of a stopped session).
    std::lock_guard lock(mutex_);
    target_spp_ = spp;
  }
  wake_.notify_all();
}

bool RenderSession::fetch(SessionFrame& out) {
  std::lock_guard lock(publish_mutex_);
  if (published_.epoch == out.epoch && published_.frames == out.frames && published_.preview == out.preview &&
      published_.revision == out.revision)
    return false;
  if (published_.epoch < out.epoch) return false;
  out = published_;  // every field; the vectors reuse out's storage when it is large enough
  return true;
}

void RenderSession::drive(std::stop_token stop) {
  using Clock = std::chrono::steady_clock;
  std::unique_ptr<Renderer> renderer;
  int renderer_threads = -1;
  ProgressiveFilm film;
  uint64_t current = 0;
  std::shared_ptr<const RenderScene> scene;
  RenderParams params;
  int frames = 0;
  double seconds = 0.0;
  RenderCounters counters;
  bool need_preview = false;
  auto publish = [&](Image image, bool preview, int w, int h) {
    std::lock_guard lock(publish_mutex_);
    published_.epoch = current;
    published_.preview = preview;
    published_.frames = frames;
    ++published_.revision;
    published_.spp = preview ? 0 : film.spp();
    published_.width = w;
    published_.height = h;
    published_.seconds = seconds;
    published_.threads = renderer->thread_count();
    published_.counters = counters;
    published_.image = std::move(image);
    published_.est_rel_mse = preview ? 0.0 : est_rel_mse(film.film());
    published_.converged_fraction = preview ? 0.0 : film.converged_fraction();
    published_.converged = !preview && film.converged();
    published_.spp_stats = preview ? SppSummary{} : spp_summary(film.film());
    bool maps = publish_maps_ && !preview;
    published_.rel_error = maps ? rel_error_image(film.film()) : Image();
    published_.spp_map = maps ? spp_image(film.film()) : Image();
    if (publish_counts_ && !preview) published_.count = film.film().count;
    else published_.count.clear();
    const float unknown = std::numeric_limits<float>::quiet_NaN();
    published_.auto_first_spread = scene->auto_pilot_pending ? unknown : scene->auto_first_spread;
    published_.auto_pilot_gain = scene->auto_pilot_pending ? unknown : scene->auto_pilot_gain;
  };
  while (!stop.stop_requested()) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, stop, [&] {
        bool target_reached = target_spp_ > 0 && film.spp() >= target_spp_ && epoch_ == current;
        // A new epoch's preview is rendered even when paused, so an edit always shows at once.
        return scene_ && (epoch_ != current || adaptive_changed_ || republish_ || need_preview ||
                          (!paused_ && !target_reached && !converged_));
      });
      if (stop.stop_requested()) break;
      if (epoch_ != current) {
        current = epoch_;
        scene = scene_;
        params = params_;
        frames = 0;
        seconds = 0.0;
        counters = {};
        film.reset(params.width, params.height);
        adaptive_changed_ = true;
        need_preview = preview_div_ > 1;
        if (renderer_threads != params.threads || !renderer) {
          renderer = std::make_unique<Renderer>(params.threads);
          renderer_threads = params.threads;
        }
      }
      if (adaptive_changed_) {
        film.set_adaptive(adaptive_);
        adaptive_changed_ = false;
        converged_ = film.converged();
        republish_ = republish_ || frames > 0;  // the stopped fraction changed, even if nothing renders now
        continue;  // re-evaluate: a converged film may have resumed, or a paused one stays paused
      }
      if (republish_) {
        republish_ = false;
        if (frames > 0 && !need_preview) {
          lock.unlock();
          publish(film.film().resolve(), false, params.width, params.height);
          continue;
        }
      }
      cancel_ = false;
    }
    RenderCounters frame_counters;
    if (need_preview) {
      RenderParams p = params;
      p.width = std::max(1, params.width / preview_div_);
      p.height = std::max(1, params.height / preview_div_);
      p.spp_per_frame = 1;
      Film small(p.width, p.height);
      bool done = renderer->render_frame(*scene, p, small, 0, frame_counters, &cancel_);
      if (!done || epoch_ != current) continue;
      need_preview = false;
      publish(small.resolve(), true, p.width, p.height);
      continue;
    }
    if (scene->auto_pilot_pending) {
      // The viewer's edit left LightSampling::automatic's pilot to this thread (RenderScene::auto_pilot_pending):
      // run after the preview, it is not on the way to the edit's first look.
      auto piloted = std::make_shared<RenderScene>(*scene);
      update_auto_light_sampling(*piloted);
      scene = std::move(piloted);
      if (epoch_ != current) continue;
    }
    // Frames faster than the display's updates go several to a pass (ProgressiveFilm::frames_per_pass), about
    // kInteractivePassSeconds of them, never past the target.
    const int target = target_spp_;
    const int pass_frames = film.frames_per_pass(params.spp_per_frame, frames > 0 ? seconds / frames : 0.0,
                                                 kInteractivePassSeconds, std::numeric_limits<int>::max(),
                                                 target > 0 ? target - film.spp() : std::numeric_limits<int>::max());
    RenderParams pass = params;
    pass.spp_per_frame = pass_frames * params.spp_per_frame;
    auto t0 = Clock::now();
    bool complete = film.render_frame(*renderer, *scene, pass, frame_counters, &cancel_, pass_frames);
    if (!complete || epoch_ != current) continue;  // stale: the next loop starts the new epoch
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    frames += pass_frames;
    counters += frame_counters;
    converged_ = film.converged();
    publish(film.film().resolve(), false, params.width, params.height);
  }
}

}  // namespace pt
