#pragma once
/// Linear float RGB images and their files. PNG is tonemapped 8-bit sRGB; PFM and EXR hold the linear values
/// unchanged. Every write is atomic (a temporary file in the same directory, then rename), so a failed or
/// interrupted write never leaves a partial file behind.
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/result.h"

namespace pt {

/// Row-major RGB, top row first, 3 floats per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}
  vec3 at(int x, int y) const {
    size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  void set(int x, int y, vec3 c) {
    size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
    rgb[i] = c.x; rgb[i + 1] = c.y; rgb[i + 2] = c.z;
  }
};

enum class Tonemap : int { clamp = 0, reinhard = 1, aces = 2 };

/// How linear radiance becomes a displayed color: scale by 2^exposure, tonemap, then sRGB-encode. The viewer's
/// shader (shaders/display.frag) implements the same functions.
struct DisplaySettings {
  float exposure = 0.0f;  ///< in stops
  Tonemap tonemap = Tonemap::clamp;
};

/// Tonemapped color in [0,1] (before sRGB encoding).
vec3 apply_tonemap(vec3 linear, const DisplaySettings& settings);
/// The sRGB transfer function (IEC 61966-2-1) for one channel in [0,1].
float srgb_encode(float linear);

/// Writes by extension: .png (tonemapped 8-bit sRGB), .pfm (little-endian, rows bottom to top, scale -1),
/// .exr (32-bit float RGB). Returns an error "PATH: reason" on failure, leaving no file.
std::optional<Error> save_image(const std::string& path, const Image& image, const DisplaySettings& display = {});

/// Reads a .pfm (either endianness, RGB or grey) or .exr file as linear RGB.
Result<Image> load_image(const std::string& path);

/// True if `path` ends with one of the extensions save_image understands.
bool is_supported_image_extension(const std::string& path);

/// True if `path` ends with .pfm or .exr: the linear float formats load_image reads (references) and the per-pixel
/// maps are written in.
bool is_float_image_extension(const std::string& path);

}  // namespace pt
