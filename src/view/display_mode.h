#pragma once
/// What the image area shows: the render itself or a false-colour map of its convergence (issue 12). The maps
/// are computed on the CPU from the published frame into an ordinary linear RGB image, so the GL side draws them
/// like the render (with exposure 0 and the clamp tonemap, under which the shader's sRGB encode inverts ours).
#include <cstdint>
#include <string>

#include "core/name_table.h"
#include "render/image.h"

namespace pt {

struct SessionFrame;

enum class DisplayMode : uint8_t {
  image,            ///< the render
  error,            ///< per-pixel relative standard error of the half-sample estimator, log heatmap
  samples,          ///< samples per pixel (adaptive sampling), linear heatmap
  reference_error,  ///< |x - ref| / ref against --reference, log heatmap
};
inline constexpr EnumName<DisplayMode> kDisplayModeNames[] = {{DisplayMode::image, "image"},
                                                              {DisplayMode::error, "error"},
                                                              {DisplayMode::samples, "samples"},
                                                              {DisplayMode::reference_error, "reference-error"}};

/// Whether `mode` needs the session's per-pixel maps (error and spp), which the session publishes only on demand.
inline bool needs_maps(DisplayMode mode) { return mode == DisplayMode::error || mode == DisplayMode::samples; }

/// The value range of a heatmap, for its legend (colour bar with values).
struct HeatLegend {
  std::string title;
  double lo = 0.0, hi = 1.0;
  bool log = false;  ///< ticks at powers of ten
};

/// The heatmap colour of t in [0, 1] (a 5-stop approximation of matplotlib's inferno), in sRGB [0, 1].
vec3 heat_srgb(float t);

/// Relative errors are mapped on log10 between these (the legend's ends).
inline constexpr double kRelErrorLo = 1e-3, kRelErrorHi = 1.0;

/// The linear RGB image the display shows in `mode` (the frame's own image in image mode, or when the map it needs
/// is not available: a preview frame, maps not yet published, a reference of another size); fills `legend` and
/// returns true when it is a heatmap. Unknown errors (fewer than 2 samples) are grey.
bool make_display_image(DisplayMode mode, const SessionFrame& frame, const Image* reference, Image& out,
                        HeatLegend& legend);

}  // namespace pt
