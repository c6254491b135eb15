#pragma once
/// The OpenGL side of the viewer: a float texture holding the current mean, drawn letterboxed by the display
/// shader (exposure, tonemap, sRGB), and screenshots of the whole window.
#include <optional>
#include <string>

#include "core/result.h"
#include "render/image.h"

namespace pt {

class GlDisplay {
 public:
  /// Needs a current GL 3.3 core context. Returns an error message on shader failure.
  std::string init();
  void destroy();
  /// Uploads a new image through a pixel buffer object (any size; the texture is reallocated when it changes).
  void upload(const Image& image);
  /// Draws the image letterboxed into the framebuffer rectangle (x, y, w, h) (GL coordinates, origin bottom-left).
  void draw(int x, int y, int w, int h, const DisplaySettings& display) const;
  int image_width() const { return tex_w_; }
  int image_height() const { return tex_h_; }

 private:
  unsigned program_ = 0, vao_ = 0, texture_ = 0, pbo_ = 0;
  int tex_w_ = 0, tex_h_ = 0;
  int loc_exposure_ = -1, loc_tonemap_ = -1, loc_image_ = -1;
};

/// The letterboxed rectangle of an image of size iw x ih inside a w x h area (x, y offsets and size).
struct Rect {
  int x = 0, y = 0, w = 0, h = 0;
};
Rect letterbox(int area_w, int area_h, int image_w, int image_h);

/// Reads the framebuffer (w x h) and writes it as PNG, atomically.
std::optional<Error> save_framebuffer_png(const std::string& path, int w, int h);

}  // namespace pt
