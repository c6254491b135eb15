#pragma once
/// The ImGui side column: Render, Camera, Material, Light, Scene, Display and Stats panels. Only real value
/// changes restart rendering; opening, hovering or collapsing a panel never does.
#include <string>

#include "view/viewer_state.h"

namespace pt {

struct PanelState {
  std::string save_path = "ptview.png";
  std::string open_path;
  bool open_material = false;  ///< set when the user picks an object, to bring the Material panel forward
  int target_spp = 0;
};

void draw_panels(ViewerState& st, PanelState& ps, float width, float height);

}  // namespace pt
