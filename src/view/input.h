#pragma once
/// Mouse and keyboard to edits: drags orbit and pan, the wheel dollies, WASD/QE fly, F frames, R resets, a click
/// without motion picks. Everything becomes an Edit applied through ViewerState::apply.
#include <optional>
#include <string>
#include <vector>

#include "view/display.h"
#include "view/viewer_state.h"

struct GLFWwindow;

namespace pt {

struct InputState {
  bool dragging[3] = {false, false, false};
  double press_x = 0, press_y = 0, last_x = 0, last_y = 0;
  bool drag_moved = false;
  bool r_was_down = false, f_was_down = false;
  double scroll = 0.0;                ///< wheel steps since the last frame (from the GLFW callback)
  std::vector<std::string> dropped;   ///< files dropped since the last frame
};

/// Where the image is drawn, in framebuffer pixels (GL origin bottom-left), and the window-to-framebuffer scale.
struct ImageArea {
  Rect rect;          ///< the render, letterboxed into the area right of the panel column
  int fb_height = 0;
  float to_fb = 1.0f;
  int panel_px = 0;   ///< the panel column's width
  int w = 1, h = 1;   ///< the area right of the panel column (what a window-sized render fills)
  bool empty = false; ///< no pixel right of the panels (a minimized window, or one narrower than the panels)
};

/// This frame's image area: a framebuffer of fb_w x fb_h pixels behind a window win_w units wide (HiDPI screens
/// have more pixels than units), a panel column panel_w units wide on the left, a render of render_w x render_h.
ImageArea image_area(int fb_w, int fb_h, int win_w, float panel_w, int render_w, int render_h);

/// The render size a window-sized render follows: the image area's, at most 16384 on a side.
ivec2 followed_size(const ImageArea& area);

/// Whether the render follows the image area: not when its size is locked, nor while the area is empty.
inline bool follows_area(const ImageArea& area, bool locked) { return !locked && !area.empty; }

/// Follows the window: once the image area has kept one size for `debounce` seconds (a drag is not a restart
/// storm) and that size differs from the render's, update() returns the size to resize the render to. A locked
/// size (--size, the Render panel's lock) and an empty area (a minimized window: its framebuffer is 0 x 0) are not
/// followed: minimizing the window must not throw the accumulated image away.
struct SizeFollower {
  double debounce = 0.25;
  ivec2 want{0, 0};
  double since = 0.0;
  std::optional<ivec2> update(const ImageArea& area, bool locked, ivec2 render, double now_seconds);
};

/// The render pixel under a window point (GLFW cursor units, origin top-left), or nothing outside the image: what a
/// click picks.
std::optional<ivec2> render_pixel_at(const ImageArea& area, double mx, double my, int render_w, int render_h);

/// The A/B compare divider at `divider` (a fraction of the image width) as a window x (GLFW cursor units), and
/// back: the divider a cursor at window x puts there (unclamped; DividerEdit clamps it to [0, 1]).
double divider_window_x(const ImageArea& area, float divider);
float divider_at(const ImageArea& area, double mx);
/// Whether a press at window x grabs the divider: within 6 window units of it, whatever the framebuffer scale.
bool grabs_divider(const ImageArea& area, float divider, double mx);

/// Drags the compare divider: a press that grabs it takes the mouse (no orbit) until release. `dragging` carries
/// the drag from frame to frame. Returns true while the divider has the mouse.
bool drag_divider(GLFWwindow* window, ViewerState& st, const ImageArea& area, bool ui_mouse, bool& dragging);

/// Handles this UI frame's input. `ui_mouse`/`ui_keyboard`: ImGui wants them. Returns true when a click picked
/// something (the Material panel then opens).
bool process_input(GLFWwindow* window, InputState& in, ViewerState& st, const ImageArea& area, double dt,
                   bool ui_mouse, bool ui_keyboard);

}  // namespace pt
