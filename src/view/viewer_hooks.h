#pragma once
/// Test and automation hooks of the windowed mode, set from the command line.
#include <optional>
#include <string>

#include "render/adaptive.h"

namespace pt {

struct ViewerHooks {
  std::optional<int> quit_after_frames;  ///< quit after this many rendered frames
  std::string screenshot;                ///< PNG of the window (panels included) written at exit
  std::string script;                    ///< scripted input file (see README)
  std::string stats_json;                ///< stats written at exit
  std::string out;                       ///< default file name for "save image"
  bool lock_size = false;                ///< --size given: the render size does not follow the window
  std::string reference;                 ///< --reference: true relMSE and the reference-error display mode
  AdaptiveParams adaptive;               ///< --noise-threshold, --min-spp: the initial adaptive sampling
};

}  // namespace pt
