// Where the viewer draws the render and which pixel a click picks (view/input.h), against the geometry written out
// here: the viewer tests click through scripts in render pixels, so a wrong window-to-pixel mapping passed them.
#include <gtest/gtest.h>

#include "view/input.h"

namespace pt {
namespace {

void expect_rect(const Rect& r, int x, int y, int w, int h) {
  EXPECT_EQ(r.x, x);
  EXPECT_EQ(r.y, y);
  EXPECT_EQ(r.w, w);
  EXPECT_EQ(r.h, h);
}

/// The area's scale, panel column and size in framebuffer pixels.
void expect_area(const ImageArea& a, float to_fb, int panel_px, int w, int h) {
  EXPECT_EQ(a.to_fb, to_fb);
  EXPECT_EQ(a.panel_px, panel_px);
  EXPECT_EQ(a.w, w);
  EXPECT_EQ(a.h, h);
}

TEST(ImageArea, TheRenderIsLetterboxedRightOfThePanelColumn) {
  // 1000 x 800 window, no HiDPI, 360-unit panel column: a 640 x 800 area; a 320 x 240 render scales by 2 (the
  // width decides) and is centred vertically (GL y counts from the bottom).
  const ImageArea a = image_area(1000, 800, 1000, 360.0f, 320, 240);
  expect_area(a, 1.0f, 360, 640, 800);
  expect_rect(a.rect, 360, 160, 640, 480);
  // A tall render: the height decides and it is centred horizontally in the area.
  expect_rect(image_area(1000, 800, 1000, 360.0f, 100, 400).rect, 360 + 220, 0, 200, 800);
}

TEST(ImageArea, HiDpiFramebuffersScaleThePanelAndTheArea) {
  // Two framebuffer pixels per window unit.
  const ImageArea a = image_area(2000, 1600, 1000, 360.0f, 320, 240);
  expect_area(a, 2.0f, 720, 1280, 1600);
  expect_rect(a.rect, 720, 320, 1280, 960);
}

TEST(ImageArea, AClickPicksThePixelUnderItWithRowZeroAtTheTop) {
  // The HiDPI area above: each render pixel is 4 x 4 framebuffer pixels, 2 x 2 window units; the image's top-left
  // corner is at window (360, 160) (framebuffer (720, 1600 - 320 - 960 = 320)).
  const ImageArea a = image_area(2000, 1600, 1000, 360.0f, 320, 240);
  auto pick = [&](double mx, double my) { return render_pixel_at(a, mx, my, 320, 240); };
  EXPECT_EQ(pick(360.0, 160.0), ivec2(0, 0));
  EXPECT_EQ(pick(360.0 + 2 * 10 + 1, 160.0 + 2 * 20 + 1), ivec2(10, 20));
  EXPECT_EQ(pick(360.0 + 2 * 320 - 0.01, 160.0 + 2 * 240 - 0.01), ivec2(319, 239));
  EXPECT_EQ(pick(360.0 + 1, 160.0 + 2 * 240 - 1), ivec2(0, 239)) << "bottom-left: the last row";
  // Outside the image: the panel column, the letterbox margins above and below, past the right edge.
  EXPECT_FALSE(pick(359.9, 300.0));
  EXPECT_FALSE(pick(500.0, 159.9));
  EXPECT_FALSE(pick(500.0, 160.0 + 2 * 240));
  EXPECT_FALSE(pick(360.0 + 2 * 320, 300.0));
  EXPECT_FALSE(pick(-1.0, -1.0));
}

TEST(ImageArea, AnOddMarginIsCountedFromTheTopOfTheWindow) {
  // 801 framebuffer rows: the letterbox leaves 160 rows below the image (GL's y) and 161 above it, which is where
  // the window's cursor y counts from.
  const ImageArea a = image_area(1000, 801, 1000, 360.0f, 320, 240);
  expect_rect(a.rect, 360, 160, 640, 480);
  EXPECT_FALSE(render_pixel_at(a, 500.0, 160.5, 320, 240));
  EXPECT_EQ(render_pixel_at(a, 500.0, 161.0, 320, 240), ivec2(70, 0));
  EXPECT_EQ(render_pixel_at(a, 500.0, 640.9, 320, 240), ivec2(70, 239));
  EXPECT_FALSE(render_pixel_at(a, 500.0, 641.0, 320, 240));
}

TEST(ImageArea, AMinimisedWindowHasAnAreaButNoPixelToPick) {
  // glfwGetFramebufferSize gives 0 x 0 for an iconified window: the area stays at least a pixel and nothing breaks.
  const ImageArea a = image_area(0, 0, 0, 360.0f, 320, 240);
  expect_area(a, 1.0f, 360, 1, 1);
  EXPECT_FALSE(render_pixel_at(a, 0.0, 0.0, 320, 240));
  const ImageArea none{};  // no rectangle yet: no division by its zero width
  EXPECT_FALSE(render_pixel_at(none, 0.0, 0.0, 320, 240));
}

TEST(ImageArea, AMinimisedOrTooNarrowWindowHasAnEmptyArea) {
  EXPECT_TRUE(image_area(0, 0, 0, 360.0f, 320, 240).empty);
  EXPECT_TRUE(image_area(360, 500, 360, 360.0f, 320, 240).empty);  // all panels
  EXPECT_TRUE(image_area(800, 0, 800, 360.0f, 320, 240).empty);
  EXPECT_FALSE(image_area(361, 1, 361, 360.0f, 320, 240).empty);  // one pixel
  EXPECT_EQ(followed_size(image_area(361, 1, 361, 360.0f, 320, 240)), ivec2(1, 1));
}

TEST(SizeFollower, TheRenderTakesTheAreaSizeOnceItHasBeenStableForTheDebounce) {
  SizeFollower f;
  const ImageArea area = image_area(1000, 700, 1000, 360.0f, 320, 240);  // 640 x 700
  const ivec2 render(320, 240);
  EXPECT_FALSE(f.update(area, false, render, 10.0));  // a new size: the debounce starts
  EXPECT_FALSE(f.update(area, false, render, 10.2));
  EXPECT_EQ(f.update(area, false, render, 10.25), ivec2(640, 700));
  EXPECT_FALSE(f.update(area, false, ivec2(640, 700), 11.0));  // followed: nothing more to do
  // A drag: each new size restarts the debounce, so no resize happens until the size holds still.
  const ImageArea taller = image_area(1000, 720, 1000, 360.0f, 320, 240);
  EXPECT_FALSE(f.update(taller, false, ivec2(640, 700), 11.1));
  EXPECT_FALSE(f.update(area, false, ivec2(640, 700), 11.3));  // back to the render's size: nothing to follow
  EXPECT_FALSE(f.update(taller, false, ivec2(640, 700), 11.4));
  EXPECT_FALSE(f.update(taller, false, ivec2(640, 700), 11.6));
  EXPECT_EQ(f.update(taller, false, ivec2(640, 700), 11.7), ivec2(640, 720));
}

TEST(SizeFollower, ALockedSizeOrAMinimisedWindowIsNotFollowed) {
  const ImageArea area = image_area(1000, 700, 1000, 360.0f, 320, 240);
  SizeFollower f;
  for (double t = 0.0; t < 2.0; t += 0.1) EXPECT_FALSE(f.update(area, true, ivec2(320, 240), t)) << t;
  // Minimised (a 0 x 0 framebuffer): the render keeps its size and its samples.
  const ImageArea minimised = image_area(0, 0, 0, 360.0f, 320, 240);
  for (double t = 0.0; t < 2.0; t += 0.1) EXPECT_FALSE(f.update(minimised, false, ivec2(320, 240), t)) << t;
  // A huge window: the render is held to 16384 on a side.
  const ImageArea huge = image_area(40000, 20000, 40000, 360.0f, 320, 240);
  EXPECT_EQ(followed_size(huge), ivec2(16384, 16384));
  EXPECT_FALSE(f.update(huge, false, ivec2(320, 240), 5.0));
  EXPECT_EQ(f.update(huge, false, ivec2(320, 240), 5.3), ivec2(16384, 16384));
}

TEST(ImageArea, TheDividerFollowsTheCursorAcrossTheImage) {
  // The HiDPI area of the tests above: the image spans window x 360 to 360 + 640.
  const ImageArea a = image_area(2000, 1600, 1000, 360.0f, 320, 240);
  EXPECT_DOUBLE_EQ(divider_window_x(a, 0.0f), 360.0);
  EXPECT_DOUBLE_EQ(divider_window_x(a, 0.25f), 360.0 + 160.0);
  EXPECT_DOUBLE_EQ(divider_window_x(a, 1.0f), 1000.0);
  EXPECT_FLOAT_EQ(divider_at(a, 360.0 + 160.0), 0.25f);
  EXPECT_FLOAT_EQ(divider_at(a, 360.0 + 480.0), 0.75f);
  EXPECT_LT(divider_at(a, 300.0), 0.0f) << "unclamped left of the image (DividerEdit clamps)";
  // A letterboxed wide render in a plain window: the divider is a fraction of the image, not of the area.
  const ImageArea b = image_area(1000, 800, 1000, 360.0f, 100, 400);  // image at x 580 to 780
  EXPECT_DOUBLE_EQ(divider_window_x(b, 0.5f), 680.0);
  EXPECT_FLOAT_EQ(divider_at(b, 630.0), 0.25f);
  EXPECT_FLOAT_EQ(divider_at(ImageArea{}, 10.0), 0.5f) << "no image yet: no division by its zero width";
}

TEST(ImageArea, APressGrabsTheDividerWithinSixWindowUnits) {
  for (const int scale : {1, 2}) {
    const ImageArea a = image_area(1000 * scale, 800 * scale, 1000, 360.0f, 320, 240);
    const double line = divider_window_x(a, 0.5f);  // 680 at either scale
    EXPECT_DOUBLE_EQ(line, 680.0);
    EXPECT_TRUE(grabs_divider(a, 0.5f, line));
    EXPECT_TRUE(grabs_divider(a, 0.5f, line - 6.0));
    EXPECT_TRUE(grabs_divider(a, 0.5f, line + 6.0));
    EXPECT_FALSE(grabs_divider(a, 0.5f, line - 6.5)) << scale;
    EXPECT_FALSE(grabs_divider(a, 0.5f, line + 6.5)) << scale;
    EXPECT_FALSE(grabs_divider(a, 0.25f, line));
  }
}

}  // namespace
}  // namespace pt
