#pragma once
/// Error of an image against a reference: one definition shared by the headless --error-csv and the viewer's
/// Stats panel and reference-error display mode.
#include "render/image.h"

namespace pt {

/// Root-mean-square error and relative MSE (mean of (x - r)^2 / (r^2 + 0.01) over pixels and channels).
struct ImageError {
  double rmse = 0.0;
  double rel_mse = 0.0;
};
/// Zero error when the sizes differ or either image is empty.
ImageError compare_images(const Image& image, const Image& reference);

}  // namespace pt
