// The progressive session: restarts never block, stale work is discarded, frames of the final state accumulate
// exactly as a direct render would (same samples, same image).
#include <gtest/gtest.h>

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <thread>

#include "render/auto_light_sampling.h"
#include "render/session.h"
#include "scene_builders.h"

namespace pt {
namespace {

SessionFrame wait_for_frames(RenderSession& s, uint64_t epoch, int frames) {
  SessionFrame f;
  for (int i = 0; i < 20000; ++i) {
    s.fetch(f);
    if (f.epoch == epoch && !f.preview && f.frames >= frames) return f;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ADD_FAILURE() << "timed out waiting for epoch " << epoch << " frame " << frames;
  return f;
}

/// A small image on 2 threads: frames of a few milliseconds.
RenderParams small_params(int width, int height, int spp_per_frame = 1) {
  RenderParams p;
  p.width = width;
  p.height = height;
  p.threads = 2;
  p.spp_per_frame = spp_per_frame;
  return p;
}

TEST(Session, FinalStateMatchesADirectRender) {
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  RenderParams p = small_params(24, 16);
  RenderSession session(2);
  session.set_preview_divisor(4);
  session.set_target_spp(3);  // before the first frame: fast frames go several to a pass
  // A storm of restarts: each must return at once and leave only the last state rendering.
  uint64_t last = 0;
  for (int i = 0; i < 50; ++i) {
    p.seed = uint64_t(i);
    last = session.restart(rs, p);
  }
  SessionFrame f = wait_for_frames(session, last, 3);
  EXPECT_EQ(f.spp, 3);
  // The same three frames rendered directly.
  Renderer r(1);
  Film film(p.width, p.height);
  RenderCounters c;
  for (uint32_t k = 0; k < 3; ++k) r.render_frame(*rs, p, film, k, c);
  Image direct = film.resolve();
  EXPECT_EQ(f.image.rgb, direct.rgb);
  EXPECT_EQ(f.counters.samples, c.samples);
}

TEST(Session, RunsAPendingAutoLightSamplingPilotBeforeItsFirstKeptFrame) {
  // The viewer's edits leave the pilot to the session (RenderScene::auto_pilot_pending). A scene whose stored choice
  // is the wrong one must still render, frame for frame, what the piloted scene renders directly.
  const RenderScene piloted = make_render_scene(test::make_test_cornell());
  auto pending = std::make_shared<RenderScene>(piloted);
  pending->auto_first_spread = piloted.auto_first_spread == kAutoMinSpread ? kAutoMinSpreadDeep : kAutoMinSpread;
  pending->auto_pilot_pending = true;
  const RenderParams p = small_params(24, 16);
  Renderer r(1);
  Film stale(p.width, p.height), right(p.width, p.height);
  RenderCounters c;
  for (uint32_t k = 0; k < 3; ++k) r.render_frame(*pending, p, stale, k, c), r.render_frame(piloted, p, right, k, c);
  ASSERT_NE(stale.resolve().rgb, right.resolve().rgb) << "the choices must differ here for the test to tell";
  RenderSession session(2);
  session.set_preview_divisor(4);
  session.set_target_spp(3);
  const uint64_t epoch = session.restart(pending, p);
  const SessionFrame f = wait_for_frames(session, epoch, 3);
  EXPECT_EQ(f.image.rgb, right.resolve().rgb);
  // The frame tells the viewer what was chosen (its Stats panel).
  EXPECT_EQ(f.auto_first_spread, piloted.auto_first_spread);
  EXPECT_EQ(f.auto_pilot_gain, piloted.auto_pilot_gain);
}

/// The mean after `frames` frames rendered directly, the image a session of the same state must publish.
Image direct_render(const RenderScene& rs, const RenderParams& p, int frames) {
  Renderer r(1);
  Film film(p.width, p.height);
  RenderCounters c;
  for (int k = 0; k < frames; ++k) r.render_frame(rs, p, film, uint32_t(k), c);
  return film.resolve();
}

// Frames far faster than the display go several to a pass (ProgressiveFilm::frames_per_pass), but a pass never
// runs past the target: with 3 samples a frame and a target of 10 the session stops after 4 frames, 12 samples,
// as it would frame by frame, and shows what 4 frames rendered directly show.
TEST(Session, PassesOfSeveralFramesStopAtTheTarget) {
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  const RenderParams p = small_params(20, 12, 3);
  for (int target : {10, 12}) {  // 12: met exactly by whole frames, and no fifth frame after it
    SCOPED_TRACE(target);
    RenderSession session(2);
    session.set_target_spp(target);
    const uint64_t epoch = session.restart(rs, p);
    SessionFrame f = wait_for_frames(session, epoch, 4);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // it has stopped: nothing newer comes
    session.fetch(f);
    EXPECT_EQ(f.frames, 4);
    EXPECT_EQ(f.spp, 12);
    EXPECT_EQ(f.image.rgb, direct_render(*rs, p, 4).rgb);
  }
}

TEST(Session, ANewEpochStartsItsTimeAndCountersAtZero) {
  // The first epoch renders a few heavy frames; the second, one light frame of the same scene. Its time is within
  // the wall time since its restart, and its counters are those of that frame alone, as a fresh session's.
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  RenderSession session(2);
  const RenderParams light = small_params(8, 8);
  RenderCounters fresh;
  {
    RenderSession other(2);
    other.set_target_spp(1);
    fresh = wait_for_frames(other, other.restart(rs, light), 1).counters;
  }
  session.set_target_spp(64);
  const SessionFrame heavy = wait_for_frames(session, session.restart(rs, small_params(64, 64, 16)), 4);
  ASSERT_GT(heavy.seconds, 0.0);
  session.set_target_spp(1);
  const auto t0 = std::chrono::steady_clock::now();
  const SessionFrame f = wait_for_frames(session, session.restart(rs, light), 1);
  const double since_restart = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LE(f.seconds, since_restart);
  EXPECT_EQ(f.counters.rays(), fresh.rays());
  EXPECT_EQ(f.counters.nonfinite_samples, fresh.nonfinite_samples);
}

TEST(Session, AFrameNamesTheThreadsThatRenderedIt) {
  // The viewer's thread slider restarts with another RenderParams::threads: the next epoch renders with that many
  // workers, and its frames say so (the Stats panel and the stats JSON show it).
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  RenderSession session(2);
  session.set_target_spp(1);
  RenderParams p = small_params(8, 8);
  p.threads = 1;
  EXPECT_EQ(wait_for_frames(session, session.restart(rs, p), 1).threads, 1);
  p.threads = 3;
  EXPECT_EQ(wait_for_frames(session, session.restart(rs, p), 1).threads, 3);
}

TEST(Session, SwitchingMapsOnOrChangingAdaptiveSamplingRepublishesAPausedFrame) {
  // Nothing renders while paused, yet the heatmaps asked for, and the pixels a new threshold stops, show at once.
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  const RenderParams p = small_params(16, 16);
  RenderSession session(2);
  session.set_target_spp(8);
  SessionFrame f = wait_for_frames(session, session.restart(rs, p), 8);
  session.set_paused(true);
  ASSERT_TRUE(f.rel_error.rgb.empty());
  EXPECT_EQ(f.converged_fraction, 0.0);
  session.set_publish_maps(true);
  SessionFrame g = f;
  for (int i = 0; i < 5000 && g.rel_error.rgb.empty(); ++i) {
    session.fetch(g);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(g.frames, f.frames);
  EXPECT_FALSE(g.rel_error.rgb.empty());
  AdaptiveParams loose;
  loose.noise_threshold = 1e6;  // every pixel is below it
  loose.min_spp = 4;
  session.set_adaptive(loose);
  SessionFrame h = g;
  for (int i = 0; i < 5000 && !(h.converged_fraction > 0.0); ++i) {
    session.fetch(h);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(h.frames, f.frames);
  EXPECT_EQ(h.converged_fraction, 1.0);
}

TEST(Session, PausedSessionKeepsItsImageAndResumes) {
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  RenderParams p;
  p.width = p.height = 16;
  RenderSession session(2);
  uint64_t e = session.restart(rs, p);
  wait_for_frames(session, e, 2);
  session.set_paused(true);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  SessionFrame a;
  session.fetch(a);  // at most one frame was in flight when pausing: this is the paused state
  ASSERT_EQ(a.epoch, e);
  ASSERT_GE(a.frames, 2);
  EXPECT_EQ(a.image.rgb, direct_render(*rs, p, a.frames).rgb);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  SessionFrame b = a;
  EXPECT_FALSE(session.fetch(b));  // nothing new while paused
  EXPECT_EQ(b.image.rgb, a.image.rgb);
  // Resuming continues the same accumulation: frames a.frames, a.frames + 1, ... are added to the kept image, so
  // the result equals a direct render of that many frames (a cleared film or repeated frames would differ).
  session.set_paused(false);
  SessionFrame c = wait_for_frames(session, e, a.frames + 2);
  EXPECT_EQ(c.epoch, e);
  EXPECT_EQ(c.spp, c.frames * p.spp_per_frame);
  EXPECT_EQ(c.image.rgb, direct_render(*rs, p, c.frames).rgb);
  EXPECT_NE(c.image.rgb, a.image.rgb);
}

TEST(Session, DestroyingWhileRenderingDoesNotHang) {
  // A watchdog of its own: if destruction hangs, the test fails (abort with a message) instead of blocking ctest
  // until its 900 s timeout. 120 s is generous: each destruction waits for at most one 256x256 tile row of work.
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  std::thread watchdog([&] {
    std::unique_lock lock(m);
    if (!cv.wait_for(lock, std::chrono::seconds(120), [&] { return done; })) {
      std::fprintf(stderr, "Session.DestroyingWhileRenderingDoesNotHang: destructor hung for 120 s\n");
      std::abort();
    }
  });
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  RenderParams p;
  p.width = p.height = 256;
  p.spp_per_frame = 16;  // a frame takes far longer than the 5 ms below: destruction meets a frame in flight
  for (int i = 0; i < 5; ++i) {
    RenderSession session(2);
    session.restart(rs, p);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  {
    std::lock_guard lock(m);
    done = true;
  }
  cv.notify_all();
  watchdog.join();
}

}  // namespace
}  // namespace pt
