#pragma once
/// Everything the command line sets: one struct shared by the headless path and the viewer (yocto-gl habit).
#include <optional>
#include <string>
#include <variant>

#include "core/result.h"
#include "render/adaptive.h"
#include "render/image.h"
#include "render/integrator.h"
#include "view/viewer_hooks.h"

namespace pt {

struct AppOptions {
  std::string scene_path;            ///< empty: the built-in default scene
  RenderParams render;
  DisplaySettings display;
  std::optional<int> frames;         ///< set: headless
  std::string out;                   ///< output image (headless default "ptview.png")
  bool out_given = false;
  std::string stats_json;
  std::string reference;
  std::string error_csv;
  std::optional<double> time_limit;  ///< seconds
  std::optional<int> camera;         ///< --camera N: the scene file's camera N (glTF cameras, in node order)
  std::optional<int> max_spp;        ///< headless: stop when the most-sampled pixel has this many samples
  AdaptiveParams adaptive;           ///< --noise-threshold, --min-spp
  std::string error_map;             ///< per-pixel relative standard error (.pfm/.exr)
  std::string spp_map;               ///< samples per pixel (.pfm/.exr)
  ViewerHooks viewer;                ///< windowed mode only

  bool headless() const { return frames.has_value() || time_limit.has_value() || max_spp.has_value(); }
};

/// What parsing the command line decided: run with options, or exit now with a code after printing `message`
/// (help text on stdout with code 0, or one error line on stderr with code 2).
struct ParseOutcome {
  std::optional<AppOptions> options;
  int exit_code = 0;
  std::string message;
};

ParseOutcome parse_command_line(int argc, const char* const* argv);

}  // namespace pt
