// The accumulation film (render/film.h): what add, note_taken, mean, resolve, clear and for_each_buffer keep, each
// channel and each buffer apart (the other tests see films only through whole renders, where a channel written as
// another, or a half counted in full, hides in the noise).
#include <gtest/gtest.h>

#include <vector>

#include "render/film.h"

namespace pt {
namespace {

TEST(Film, ResolveIsThePerChannelMeanAndBlackWhereNothingLanded) {
  Film film(3, 2);
  film.add(1, vec3(1.0f, 2.0f, 4.0f), 0);
  film.add(1, vec3(3.0f, 6.0f, 8.0f), 1);
  film.add(5, vec3(0.5f, 0.25f, 0.125f), 7);
  const Image img = film.resolve();
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 2);
  const std::vector<float> expected = {0, 0, 0, 2, 4, 6, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 0.25f, 0.125f};
  EXPECT_EQ(img.rgb, expected);
  EXPECT_EQ(film.mean(0), vec3(0.0f)) << "a pixel without samples is black, not 0 / 0";
}

TEST(Film, TheHalfSumsHoldTheEvenSamplesOnly) {
  Film film(1, 1);
  for (uint64_t index = 0; index < 5; ++index) film.add(0, vec3(float(index + 1), 0.0f, 1.0f), index);
  EXPECT_EQ(film.count[0], 5u);
  EXPECT_EQ(film.half_count[0], 3u);  // indices 0, 2, 4
  EXPECT_EQ(film.sum[0], 15.0);
  EXPECT_EQ(film.half_sum[0], 1.0 + 3.0 + 5.0);
  EXPECT_EQ(film.half_sum[2], 3.0);
}

TEST(Film, TakenCountsEverySampleAndClearResetsEveryBuffer) {
  Film film(2, 1);
  film.note_taken(1);
  film.note_taken(1);
  film.add(1, vec3(1.0f), 0);  // one of the two was finite
  EXPECT_EQ(film.taken, (std::vector<uint32_t>{0, 2}));
  EXPECT_EQ(film.count, (std::vector<uint32_t>{0, 1}));
  int buffers = 0;
  film.for_each_buffer([&](auto span) {
    ++buffers;
    bool any = false;
    for (auto v : span) any |= v != 0;
    EXPECT_TRUE(any) << "buffer " << buffers << " holds the sample";
  });
  EXPECT_EQ(buffers, 5);
  film.clear();
  EXPECT_EQ(film.width, 2);
  EXPECT_EQ(film.height, 1);
  film.for_each_buffer([&](auto span) {
    for (auto v : span) EXPECT_EQ(v, 0) << "a cleared film starts again from nothing";
  });
}

}  // namespace
}  // namespace pt
