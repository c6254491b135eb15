// Rank 0's side of the viewer offload (view/offload.h) without MPI: a fake channel delivers a worker's result, and
// the frame shown is the exact per-pixel merge of rank 0's samples and the worker's; a result of an older epoch is
// dropped on arrival; every restart posts one epoch. (Under mpirun: tests/view/test_viewer.cpp, Offload*.)
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <utility>
#include <thread>

#include "render/render_scene.h"
#include "render/renderer.h"
#include "scene/load.h"
#include "view/offload.h"
#include "fake_offload.h"

namespace pt {
namespace {

using test::FakeChannel;
using test::Wire;
using test::worker_film;

TEST(Offload, AResultWhoseSizesDisagreeIsRefused) {
  // A result's sums and counts must cover its width x height: merging reads them per pixel of rank 0's frame.
  const std::vector<uint8_t> good = encode_offload_result(3, 1, 5, 0.5, worker_film(vec3(1.0f), 5));
  OffloadResult res;
  ASSERT_TRUE(decode_offload_result(good, res));
  EXPECT_EQ(res.width, 8);
  EXPECT_EQ(res.count.size(), 64u);
  std::vector<uint8_t> wider = good;
  const int32_t width = 9;  // after the epoch (8 bytes) and the rank (4): the width
  std::memcpy(wider.data() + 12, &width, 4);
  EXPECT_FALSE(decode_offload_result(wider, res));
  EXPECT_FALSE(decode_offload_result(std::vector<uint8_t>(good.begin(), good.end() - 1), res));  // cut short
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
    // Ranks that cannot send: rank 0 itself and one past the ranks set. Ignored.
    channel.results.push_back(encode_offload_result(epoch, 0, 9, 0.5, worker_film(vec3(50.0f), 9)));
    channel.results.push_back(encode_offload_result(epoch, 2, 9, 0.5, worker_film(vec3(50.0f), 9)));
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
    // A moved light refits the geometry: it travels again, as after a rebuild.
    root.post_epoch(next + 1, params, *scene, 1, 1);
    ASSERT_EQ(channel.posted.size(), 3u);
    EXPECT_EQ(channel.posted[2].size(), channel.posted[0].size());
  }
  // Destroying the root ends the workers: an empty post.
  ASSERT_EQ(channel.posted.size(), 4u);
  EXPECT_TRUE(channel.posted.back().empty());
}

/// A worker's side of the wire, its posts left to the test: what the worker sent, in order.
struct WorkerSide : OffloadChannel {
  std::vector<std::vector<uint8_t>> sent;
  /// The newest result sent; false before any.
  bool last_sent(OffloadResult& r) const { return !sent.empty() && decode_offload_result(sent.back(), r); }
  void post(std::vector<uint8_t>) override {}
  std::vector<std::vector<uint8_t>> poll_results() override { return {}; }
  void close() override {}
  bool send_result(std::vector<uint8_t> m) override {
    sent.push_back(std::move(m));
    return true;
  }
  void finish() override {}
};

/// Rank 0's epochs on the first polls, then the end once the worker has sent a result of at least `stop_spp`
/// samples.
struct WorkerChannel final : WorkerSide {
  std::vector<std::vector<uint8_t>> epochs;  ///< delivered one a poll; the last one's results end the run
  uint64_t last_epoch;
  int stop_spp;
  size_t posted = 0;
  WorkerChannel(std::vector<std::vector<uint8_t>> e, uint64_t last, int stop)
      : epochs(std::move(e)), last_epoch(last), stop_spp(stop) {}
  std::vector<std::vector<uint8_t>> poll_posts() override {
    if (posted < epochs.size()) return {epochs[posted++]};
    OffloadResult last;
    if (last_sent(last) && last.epoch == last_epoch && last.spp >= stop_spp) return {{}};
    return {};
  }
};

/// 16x16 pixels, 4 bounces: frames of well under a millisecond.
RenderParams worker_params() {
  RenderParams p;
  p.width = p.height = 16;
  p.max_depth = 4;
  return p;
}

/// What rank 0 posts for `scenes` loaded one after the other: epochs 7, 8, ..., each a rebuild.
std::vector<std::vector<uint8_t>> posted_epochs(int ranks, const RenderParams& params,
                                                const std::vector<const Scene*>& scenes) {
  Wire wire;
  {
    OffloadRoot root(std::make_unique<FakeChannel>(&wire));
    root.set_ranks(ranks);
    for (size_t i = 0; i < scenes.size(); ++i) root.post_epoch(7 + i, params, *scenes[i], int(i) + 1, 0);
  }
  EXPECT_EQ(wire.posted.size(), scenes.size() + 1);
  wire.posted.pop_back();  // the end of the run, posted when the root goes
  return wire.posted;
}

/// Every result of `epoch` among `sent` is the film of exactly `rank`'s first `spp` samples of every pixel of
/// `scene`, as one render of that range gives it; their spp grow and reach `stop_spp`.
void expect_films_of_the_rank_range(const std::vector<std::vector<uint8_t>>& sent, const Scene& scene,
                                    const RenderParams& params, int rank, uint64_t epoch, int stop_spp) {
  const RenderScene rs = make_render_scene(scene);
  Renderer renderer(1);
  int last_spp = 0;
  for (const std::vector<uint8_t>& bytes : sent) {
    OffloadResult res;
    ASSERT_TRUE(decode_offload_result(bytes, res));
    if (res.epoch != epoch) continue;  // an earlier epoch's
    EXPECT_EQ(res.rank, rank);
    ASSERT_EQ(res.width, params.width);
    EXPECT_GT(res.spp, last_spp);
    last_spp = res.spp;
    Film direct(params.width, params.height);
    RenderParams p = params;
    p.spp_per_frame = res.spp;
    RenderCounters c;
    std::vector<uint32_t> first(direct.pixel_count(), 0);
    renderer.render_range(rs, p, direct, nullptr, first.data(), uint32_t(rank) << kRankSampleShift, c);
    for (size_t i = 0; i < direct.pixel_count(); ++i) {
      ASSERT_EQ(res.count[i], direct.count[i]) << "pixel " << i << " at " << res.spp << " spp";
      for (int k = 0; k < 3; ++k) ASSERT_EQ(res.sum[3 * i + size_t(k)], float(direct.sum[3 * i + size_t(k)])) << i;
    }
  }
  EXPECT_GE(last_spp, stop_spp);
}

TEST(Offload, WorkerPassesGiveTheFilmOfItsSampleRange) {
  // A worker renders several frames to a pass (about 1/30 s; these 16x16 frames take well under a millisecond, so
  // passes of up to kMaxFramesPerPass). Every result it sends must be the film of exactly its rank's first `spp`
  // samples of every pixel, as one render of that range gives it: no sample skipped, repeated or from another
  // rank's range.
  Result<Scene> scene = load_builtin_scene("cornell");
  ASSERT_TRUE(scene.ok());
  const RenderParams params = worker_params();
  constexpr int kRank = 2, kStopSpp = 200;
  WorkerChannel channel(posted_epochs(3, params, {&*scene}), 7, kStopSpp);
  EXPECT_EQ(run_offload_worker(channel, kRank, 2), 0);
  ASSERT_GE(channel.sent.size(), 2u);
  expect_films_of_the_rank_range(channel.sent, *scene, params, kRank, 7, kStopSpp);
}

TEST(Offload, AWorkerRebuildsItsTreeForANewScene) {
  // Two epochs, the second after a load (a rebuild): the worker renders the second scene's geometry, not the
  // first's tree with the second's materials and camera.
  Result<Scene> first = load_builtin_scene("cornell");
  ASSERT_TRUE(first.ok());
  Scene moved = *first;
  const vec3 d(0.3f, -0.2f, 0.1f);
  for (Quad& q : moved.quads) q.corner += d;
  for (Sphere& s : moved.spheres) s.center += d;
  for (Mesh& m : moved.meshes) m.origin += dvec3(d);
  // And a card in front of the camera whose shading normals lean away from its flat normal: they travel too.
  ASSERT_TRUE(moved.camera.has_value());
  const Camera& cam = *moved.camera;
  const vec3 forward = glm::normalize(cam.target - cam.eye), right = glm::normalize(glm::cross(forward, cam.up));
  const vec3 up = glm::cross(right, forward), center = cam.eye + 2.0f * forward;
  Mesh card;
  card.name = "card";
  card.positions = {center - 0.3f * right - 0.3f * up, center + 0.3f * right - 0.3f * up,
                    center + 0.3f * right + 0.3f * up, center - 0.3f * right + 0.3f * up};
  card.indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
  card.normals = {glm::normalize(-forward + right), glm::normalize(-forward - up)};
  card.normal_indices = {uvec3(0, 0, 1), uvec3(0, 1, 1)};
  card.materials = {0, 0};
  moved.meshes.push_back(card);
  const RenderParams params = worker_params();
  WorkerChannel channel(posted_epochs(2, params, {&*first, &moved}), 8, 16);
  EXPECT_EQ(run_offload_worker(channel, 1, 2), 0);
  expect_films_of_the_rank_range(channel.sent, moved, params, 1, 8, 16);
}

/// A worker's side of the wire with rank 0's pause in the middle: the epoch, a hold once the worker has sent
/// `hold_at_spp`, the release `kHeldSeconds` later, and the end once it has sent at least `stop_spp` and more
/// samples than it had when the hold settled (a worker that never resumes times out). Notes how many results the
/// worker had sent when the hold settled and at the release.
struct PausingChannel final : WorkerSide {
  static constexpr double kHeldSeconds = 1.5;
  std::vector<uint8_t> epoch, hold, release;
  int hold_at_spp, stop_spp;
  int stage = 0;  // 0: epoch to deliver, 1: running, 2: held, 3: released
  std::chrono::steady_clock::time_point stage_start = std::chrono::steady_clock::now();
  size_t sent_when_settled = 0;  ///< results sent by 0.5 s into the hold (the pass in flight then has gone)
  size_t sent_at_release = 0;
  int spp_when_settled = 0;
  bool timed_out = false;
  PausingChannel(std::vector<uint8_t> e, std::vector<uint8_t> h, std::vector<uint8_t> r, int hold_spp, int stop)
      : epoch(std::move(e)), hold(std::move(h)), release(std::move(r)), hold_at_spp(hold_spp), stop_spp(stop) {}
  int last_spp() const {
    OffloadResult last;
    return last_sent(last) ? last.spp : 0;
  }
  std::vector<std::vector<uint8_t>> poll_posts() override {
    using namespace std::chrono;
    const double in_stage = duration<double>(steady_clock::now() - stage_start).count();
    if (in_stage > 60.0) {  // a worker that never resumes (or never renders) ends the test instead of hanging it
      timed_out = true;
      return {{}};
    }
    auto next = [&](int s) {
      stage = s;
      stage_start = steady_clock::now();
    };
    switch (stage) {
      case 0:
        next(1);
        return {epoch};
      case 1:
        if (last_spp() < hold_at_spp) return {};
        next(2);
        return {hold};
      case 2:
        if (in_stage >= 0.5 && sent_when_settled == 0) {
          sent_when_settled = sent.size();
          spp_when_settled = last_spp();
        }
        if (in_stage < kHeldSeconds) return {};
        sent_at_release = sent.size();
        next(3);
        return {release};
      default:
        return last_spp() >= stop_spp && last_spp() > spp_when_settled ? std::vector<std::vector<uint8_t>>{{}}
                                                                       : std::vector<std::vector<uint8_t>>{};
    }
  }
};

TEST(Offload, APauseHoldsTheWorkersAndResumingContinuesTheirRange) {
  // Rank 0's pause reaches the workers as a hold: a worker finishes the pass in flight and sends it (within the
  // first 0.5 s of the hold), then renders and sends nothing until the release; after it, its results continue
  // its sample range with no sample skipped or repeated (the films of its first spp samples, as before; a pass cut
  // short by the hold would leave its first tiles with samples the next pass takes again).
  Result<Scene> scene = load_builtin_scene("cornell");
  ASSERT_TRUE(scene.ok());
  RenderParams params = worker_params();
  params.width = 64;  // 12 tiles: a hold arriving mid-pass finds some tiles rendered and others not
  params.height = 48;
  Wire wire;
  {
    OffloadRoot root(std::make_unique<FakeChannel>(&wire));
    root.set_ranks(2);
    root.post_epoch(7, params, *scene, 1, 0);
    root.set_hold(true);
    root.set_hold(true);  // no change: not posted again
    root.set_hold(false);
  }
  ASSERT_EQ(wire.posted.size(), 4u);  // the epoch, the hold, the release, the end
  bool held = false;
  ASSERT_TRUE(decode_offload_hold(wire.posted[1], held));
  EXPECT_TRUE(held);
  ASSERT_TRUE(decode_offload_hold(wire.posted[2], held));
  EXPECT_FALSE(held);
  EXPECT_FALSE(decode_offload_hold(wire.posted[0], held));  // an epoch is no hold
  EXPECT_FALSE(decode_offload_hold(wire.posted[3], held));  // nor is the end

  PausingChannel channel(wire.posted[0], wire.posted[1], wire.posted[2], 16, 64);
  EXPECT_EQ(run_offload_worker(channel, 1, 2), 0);
  ASSERT_FALSE(channel.timed_out) << "the worker never reached " << channel.stop_spp << " spp";
  ASSERT_GT(channel.sent_when_settled, 0u);
  EXPECT_EQ(channel.sent_at_release, channel.sent_when_settled)
      << channel.sent_at_release - channel.sent_when_settled << " results sent while held, after the pass in flight";
  EXPECT_GE(channel.spp_when_settled, 16);
  EXPECT_GE(channel.last_spp(), 64);
  expect_films_of_the_rank_range(channel.sent, *scene, params, 1, 7, 64);
}

}  // namespace
}  // namespace pt
