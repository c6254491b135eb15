#pragma once
/// Mouse and keyboard to edits: drags orbit and pan, the wheel dollies, WASD/QE fly, F frames, R resets, a click
/// without motion picks. Everything becomes an Edit applied through ViewerState::apply.
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
  Rect rect;
  int fb_height = 0;
  float to_fb = 1.0f;
  int panel_px = 0;   ///< the panel column's width
};

/// Handles this UI frame's input. `ui_mouse`/`ui_keyboard`: ImGui wants them. Returns true when a click picked
/// something (the Material panel then opens).
bool process_input(GLFWwindow* window, InputState& in, ViewerState& st, const ImageArea& area, double dt,
                   bool ui_mouse, bool ui_keyboard);

}  // namespace pt
