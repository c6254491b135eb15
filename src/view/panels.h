#pragma once
/// The ImGui side column: Render, Camera, Material, Light, Scene, Display and Stats panels. Only real value
/// changes restart rendering; opening, hovering or collapsing a panel never does. Every change is an Edit applied
/// through ViewerState::apply, exactly as the mouse and the script make them.
#include <string>

#include "view/viewer_state.h"

namespace pt {

struct PanelState {
  std::string save_path = "ptview.png";
  std::string open_path;
  bool open_material = false;  ///< set when the user picks an object, to bring the Material panel forward
  bool lock_size = false;      ///< the render size does not follow the window (--size locks it)
  std::string scene_path = "scene.json";
  double noise_threshold = 0.01;  ///< the slider's value while adaptive sampling is off
};

void draw_panels(ViewerState& st, PanelState& ps, float width, float height);

}  // namespace pt
