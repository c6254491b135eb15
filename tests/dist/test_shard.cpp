// Sample-range sharding without MPI: every frame (sample range) is rendered by exactly one rank, and the Solo cluster
// (ptview without mpirun) passes everything through.
#include <gtest/gtest.h>

#include <vector>

#include "dist/cluster.h"

namespace pt {
namespace {

// The loop of run_headless: rounds until frames_after_rounds reaches the total, each rank its shard_frame.
TEST(Shard, EveryFrameExactlyOnce) {
  for (int ranks = 1; ranks <= 5; ++ranks) {
    for (int total = 1; total <= 23; ++total) {
      std::vector<int> times(size_t(total), 0);
      std::vector<int> per_rank(size_t(ranks), 0);
      int rounds = 0;
      for (int64_t round = 0; round * ranks < total; ++round, ++rounds)
        for (int r = 0; r < ranks; ++r) {
          int64_t f = shard_frame(round, r, ranks);
          if (f < total) {
            ++times[size_t(f)];
            ++per_rank[size_t(r)];
          }
        }
      for (int f = 0; f < total; ++f) EXPECT_EQ(times[size_t(f)], 1) << "frame " << f << " ranks " << ranks;
      EXPECT_EQ(frames_after_rounds(rounds, ranks, total), total);
      // Balanced: ranks differ by at most one frame.
      EXPECT_LE(per_rank.front() - per_rank.back(), 1);
    }
  }
}

TEST(Shard, FramesAfterRoundsWithoutALimitCountsEveryRank) {
  EXPECT_EQ(frames_after_rounds(4, 3, 0), 12);
  EXPECT_EQ(frames_after_rounds(4, 3, 10), 10);
  EXPECT_EQ(frames_after_rounds(3, 3, 10), 9);
}

TEST(Solo, IsOneProcessAndPassesThrough) {
  Cluster solo;
  EXPECT_EQ(solo.rank(), 0);
  EXPECT_EQ(solo.ranks(), 1);
  EXPECT_TRUE(solo.root());
  EXPECT_EQ(solo.default_threads(), 0);  // all cores, as without MPI
  EXPECT_TRUE(solo.any(true));
  EXPECT_FALSE(solo.any(false));
  EXPECT_EQ(solo.first_error(""), "");
  EXPECT_EQ(solo.first_error("x.json: bad"), "x.json: bad");
  Film local(3, 2), total;
  local.add(4, vec3(1.0f, 2.0f, 3.0f));
  solo.sum_films(local, total);
  EXPECT_EQ(total.sum, local.sum);
  EXPECT_EQ(total.count, local.count);
  RenderCounters c;
  c.samples = 7;
  EXPECT_EQ(solo.sum_counters(c).samples, 7u);
  auto work = solo.gather_work({5, 1.5});
  ASSERT_EQ(work.size(), 1u);
  EXPECT_EQ(work[0].spp, 5);
  EXPECT_EQ(solo.comm_ms(), 0.0);
}

// The buffers that sum over samples are listed (the MPI reduction walks exactly this list), whole.
TEST(Film, SumBuffersIncludeSumAndCount) {
  Film f(4, 3);
  bool sum = false, count = false;
  f.for_each_buffer([&](auto span) {
    if (static_cast<const void*>(span.data()) == f.sum.data()) sum = span.size() == f.sum.size();
    if (static_cast<const void*>(span.data()) == f.count.data()) count = span.size() == f.count.size();
  });
  EXPECT_TRUE(sum);
  EXPECT_TRUE(count);
}

}  // namespace
}  // namespace pt
