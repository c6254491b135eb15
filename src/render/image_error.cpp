#include "render/image_error.h"

#include <cmath>

namespace pt {

ImageError compare_images(const Image& image, const Image& reference) {
  ImageError e;
  size_t n = image.rgb.size();
  if (n == 0 || n != reference.rgb.size()) return e;
  double se = 0.0, rel = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double r = reference.rgb[i];
    double d = double(image.rgb[i]) - r;
    se += d * d;
    rel += d * d / (r * r + kRelMseFloor);
  }
  e.rmse = std::sqrt(se / double(n));
  e.rel_mse = rel / double(n);
  return e;
}

}  // namespace pt
