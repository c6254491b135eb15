// Rank 0's side of the viewer offload (view/offload.h) without MPI: a fake channel delivers a worker's result, and
// the frame shown is the exact per-pixel merge of rank 0's samples and the worker's; a result of an older epoch is
// dropped on arrival; every restart posts one epoch. (Under mpirun: tests/view/test_viewer.cpp, Offload*.)
#include <gtest/gtest.h>

#include <chrono>
#include <utility>
#include <thread>

#include "render/render_scene.h"
#include "scene/load.h"
#include "view/offload.h"

namespace pt {
namespace {

/// What rank 0 posted and what the "workers" sent; outlives the channel (the root owns and destroys it).
struct Wire {
  std::vector<std::vector<uint8_t>> posted, results;
};

struct FakeChannel final : OffloadChannel {
  Wire* wire;
  explicit FakeChannel(Wire* w) : wire(w) {}
  void post(std::vector<uint8_t> m) override { wire->posted.push_back(std::move(m)); }
  std::vector<std::vector<uint8_t>> poll_results() override { return std::exchange(wire->results, {}); }
  void close() override { post({}); }
  std::vector<std::vector<uint8_t>> poll_posts() override { return {}; }
  bool send_result(std::vector<uint8_t>) override { return false; }
  void finish() override {}
};

/// A worker film of 8x8 pixels: `n` samples of `c` in every pixel.
Film worker_film(vec3 c, int n) {
  Film f(8, 8);
  for (size_t p = 0; p < f.pixel_count(); ++p)
    for (int i = 0; i < n; ++i) f.add(p, c, uint64_t(i));
  return f;
}

TEST(Offload, RankZeroShowsTheExactMergeAndDropsStaleEpochs) {
  Result<Scene> scene = load_builtin_scene("cornell");
  ASSERT_TRUE(scene.ok());
  auto rs = std::make_shared<RenderScene>(make_render_scene(*scene));
  RenderParams params;
  params.width = params.height = 8;
  params.threads = 1;
  RenderSession session(1);
  session.set_publish_counts(true);
  session.set_target_spp(3);
  Wire channel;
  {
    OffloadRoot root(std::make_unique<FakeChannel>(&channel));
    root.set_ranks(2);
    const uint64_t epoch = session.restart(rs, params);
    root.post_epoch(epoch, params, *scene, 1, 0);
    ASSERT_EQ(channel.posted.size(), 1u);
    // Rank 0's own frame at its target: published once, then stable.
    SessionFrame own;
    for (int i = 0; i < 6000 && !(own.epoch == epoch && own.spp == 3 && !own.preview); ++i) {
      session.fetch(own);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_EQ(own.spp, 3);
    ASSERT_EQ(own.count.size(), 64u);
    // The worker's result, then one of the epoch before (rendered before the edit, arriving after): dropped.
    channel.results.push_back(encode_offload_result(epoch, 1, 5, 0.5, worker_film(vec3(1.0f, 2.0f, 3.0f), 5)));
    channel.results.push_back(encode_offload_result(epoch - 1, 1, 9, 0.5, worker_film(vec3(50.0f), 9)));
    SessionFrame shown;
    ASSERT_TRUE(root.fetch(session, shown));
    EXPECT_EQ(shown.spp, 3 + 5);
    for (size_t p = 0; p < 64; ++p) {
      const double n0 = own.count[p];
      for (int c = 0; c < 3; ++c) {
        const double expect = (own.image.rgb[3 * p + size_t(c)] * n0 + 5.0 * (c + 1)) / (n0 + 5.0);
        EXPECT_NEAR(shown.image.rgb[3 * p + size_t(c)], expect, 1e-5 * expect) << p << " " << c;
      }
    }
    auto ranks = root.contributions();
    ASSERT_EQ(ranks.size(), 2u);
    EXPECT_EQ(ranks[0].spp, 3);
    EXPECT_EQ(ranks[1].spp, 5);
    EXPECT_DOUBLE_EQ(ranks[1].spp_per_s(), 10.0);
    // A new epoch: the old epoch's result no longer counts, even if it arrives now.
    const uint64_t next = session.restart(rs, params);
    root.post_epoch(next, params, *scene, 1, 0);
    EXPECT_EQ(channel.posted.size(), 2u);
    EXPECT_LT(channel.posted[1].size(), channel.posted[0].size());  // the geometry travels only when it changed
    channel.results.push_back(encode_offload_result(epoch, 1, 7, 0.5, worker_film(vec3(50.0f), 7)));
    for (int i = 0; i < 6000 && !(shown.epoch == next && shown.spp == 3 && !shown.preview); ++i) {
      root.fetch(session, shown);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_EQ(shown.epoch, next);
    EXPECT_EQ(shown.spp, 3);  // rank 0's samples only
    EXPECT_EQ(root.contributions()[1].spp, 0);
  }
  // Destroying the root ends the workers: an empty post.
  ASSERT_EQ(channel.posted.size(), 3u);
  EXPECT_TRUE(channel.posted.back().empty());
}

}  // namespace
}  // namespace pt
