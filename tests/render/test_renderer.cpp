// The renderer's entry points (render/renderer.h) and their cancel flag: a cancelled call says so, so the session
// discards its partial frame instead of counting it as a whole one.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "render/renderer.h"
#include "scene_builders.h"

namespace pt {
namespace {

TEST(Renderer, ACancelledCallReturnsFalseAndAddsNothing) {
  const RenderScene rs = make_render_scene(test::make_test_cornell());
  RenderParams params;
  params.width = 40;
  params.height = 30;
  Renderer renderer(2);
  const std::atomic<bool> cancel{true}, go{false};
  Film film(params.width, params.height);
  RenderCounters c;
  const uint32_t frames[2] = {0, 1};
  std::vector<uint32_t> first(film.pixel_count(), 0);
  EXPECT_FALSE(renderer.render_frame(rs, params, film, 0, c, &cancel));
  EXPECT_FALSE(renderer.render_frames(rs, params, film, frames, 2, c, &cancel));
  EXPECT_FALSE(renderer.render_pass(rs, params, film, nullptr, c, &cancel));
  EXPECT_FALSE(renderer.render_range(rs, params, film, nullptr, first.data(), 0, c, &cancel));
  EXPECT_EQ(c.samples, 0u);
  EXPECT_EQ(film.taken, std::vector<uint32_t>(film.pixel_count(), 0u));
  // Not cancelled: every call renders the whole image and says so.
  EXPECT_TRUE(renderer.render_frame(rs, params, film, 0, c, &go));
  EXPECT_TRUE(renderer.render_frames(rs, params, film, frames, 2, c, &go));
  EXPECT_TRUE(renderer.render_pass(rs, params, film, nullptr, c, &go));
  EXPECT_TRUE(renderer.render_range(rs, params, film, nullptr, first.data(), 0, c, &go));
  EXPECT_EQ(c.samples, 5u * film.pixel_count());
}

}  // namespace
}  // namespace pt
