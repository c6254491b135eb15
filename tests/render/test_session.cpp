// The progressive session: restarts never block, stale work is discarded, frames of the final state accumulate
// exactly as a direct render would (same samples, same image).
#include <gtest/gtest.h>

#include <thread>

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

TEST(Session, FinalStateMatchesADirectRender) {
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  RenderParams p;
  p.width = 24;
  p.height = 16;
  p.threads = 2;
  RenderSession session(2);
  session.set_preview_divisor(4);
  // A storm of restarts: each must return at once and leave only the last state rendering.
  uint64_t last = 0;
  for (int i = 0; i < 50; ++i) {
    p.seed = uint64_t(i);
    last = session.restart(rs, p);
  }
  session.set_target_spp(3);
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
  session.fetch(a);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  SessionFrame b = a;
  EXPECT_FALSE(session.fetch(b));  // nothing new while paused
  session.set_paused(false);
  wait_for_frames(session, e, a.frames + 2);
}

TEST(Session, DestroyingWhileRenderingDoesNotHang) {
  auto rs = std::make_shared<RenderScene>(make_render_scene(test::make_test_cornell()));
  RenderParams p;
  p.width = p.height = 256;
  for (int i = 0; i < 5; ++i) {
    RenderSession session(2);
    session.restart(rs, p);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  SUCCEED();
}

}  // namespace
}  // namespace pt
