// Images depend only on (scene, options, seed): never on the thread count or the tile schedule.
#include <gtest/gtest.h>

#include "render/renderer.h"
#include "scene_builders.h"

namespace pt {
namespace {

Film render(const RenderScene& rs, RenderParams params, int threads, int frames) {
  params.threads = threads;
  Renderer renderer(threads);
  Film film(params.width, params.height);
  RenderCounters c;
  for (int f = 0; f < frames; ++f) renderer.render_frame(rs, params, film, uint32_t(f), c);
  return film;
}

TEST(Determinism, ThreadCountDoesNotChangeTheImage) {
  RenderScene rs = make_render_scene(test::make_test_cornell());
  RenderParams params;
  params.width = 40;
  params.height = 30;
  params.spp_per_frame = 2;
  Film one = render(rs, params, 1, 3);
  Film two = render(rs, params, 2, 3);
  Film five = render(rs, params, 5, 3);
  EXPECT_EQ(one.sum, two.sum);
  EXPECT_EQ(one.sum, five.sum);
  EXPECT_EQ(one.count, two.count);
}

TEST(Determinism, SeedChangesTheImageAndFramesAddNewSamples) {
  RenderScene rs = make_render_scene(test::make_test_cornell());
  RenderParams params;
  params.width = params.height = 16;
  Film a = render(rs, params, 2, 1);
  params.seed = 1;
  Film b = render(rs, params, 2, 1);
  EXPECT_NE(a.sum, b.sum);
  // Frame 1 must use new sample indices, not repeat frame 0.
  params.seed = 0;
  Film two_frames = render(rs, params, 2, 2);
  for (size_t i = 0; i < a.sum.size(); ++i)
    if (two_frames.sum[i] != 2.0 * a.sum[i]) return SUCCEED();
  FAIL() << "frame 1 repeated frame 0's samples";
}

}  // namespace
}  // namespace pt
