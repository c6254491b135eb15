#pragma once
/// Error of an image against a reference: one definition shared by the headless --error-csv and the viewer's
/// Stats panel and reference-error display mode.
#include "render/image.h"

namespace pt {

/// relMSE's floor on the squared reference: (x - r)^2 / (r^2 + kRelMseFloor), so that black pixels do not weigh
/// infinitely (the definition pbrt's and Mitsuba's comparison scripts use). Every estimate of relMSE shares it: the
/// true error here, the film's own estimate and the adaptive sampler's per-pixel error (render/convergence.h), and
/// the automatic light-sampling pilot's weights (render/auto_light_sampling.h).
inline constexpr double kRelMseFloor = 0.01;

/// Root-mean-square error and relative MSE (mean of (x - r)^2 / (r^2 + kRelMseFloor) over pixels and channels).
struct ImageError {
  double rmse = 0.0;
  double rel_mse = 0.0;
};
/// Zero error when the sizes differ or either image is empty.
ImageError compare_images(const Image& image, const Image& reference);

}  // namespace pt
