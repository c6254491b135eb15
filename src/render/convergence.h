#pragma once
/// Error estimates a film can give about itself, without a reference: the variance of each pixel's mean from the
/// difference of its two half means (the split is sample_in_half_a in render/film.h), and figures derived from it.
/// The two halves are two independent estimates of the pixel, so for halves of n_a and n_b samples (n = n_a + n_b)
///   E[(A - B)^2] = Var(A) + Var(B) = s^2 (1/n_a + 1/n_b),   Var(mean) = s^2 / n,
/// hence Var(mean) ~ (A - B)^2 n_a n_b / n^2, which is (A - B)^2 / 4 for equal halves. One such estimate per pixel
/// is noisy (one degree of freedom), but its mean over many pixels is accurate; the adaptive sampler therefore
/// dilates the unconverged region (render/adaptive.h).
#include <cstdint>

#include "render/film.h"

namespace pt {

struct PixelEstimate {
  dvec3 mean;      ///< of all samples
  dvec3 var_mean;  ///< estimated variance of `mean`
  dvec3 scale;     ///< max(min(A, B), neighbours' mean): the value the relative figures divide by (see est_rel_mse)
};
/// Per channel; false when a half is empty (the variance is unknown).
bool pixel_estimate(const Film& film, size_t pixel, PixelEstimate& e);
/// Mean and estimated variance of the mean per channel; false when a half is empty (the variance is unknown).
bool pixel_mean_variance(const Film& film, size_t pixel, dvec3& mean, dvec3& var_mean);

/// The per-pixel relative standard error on luminance, sqrt(Var(mean_L)) / sqrt(min(A_L, B_L)^2 + kRelMseFloor): a
/// pixel below T adds at most T^2 to est_rel_mse (whose scale v is at least min(A, B)). The adaptive sampler stops
/// pixels on it, so it keeps the conservative scale: a stop is a selection among noisy estimates, and where a pixel's
/// few samples missed rare bright paths, both halves are dark and alike, and the neighbours' brighter level would let
/// it stop with most of its error left (measured: with the neighbours' scale here, adaptive sampling on the glass box
/// at T = 0.1 lost all its gain over uniform sampling, 0.97x instead of 1.85x). (The floor keeps dark pixels from
/// needing an absolute error far below what rel_mse can see.) +infinity when the variance is unknown.
double pixel_rel_error(const Film& film, size_t pixel);

/// Mean over pixels and channels of Var(mean) / (v^2 + kRelMseFloor): the normalisation of rel_mse against a reference
/// (compare_images, render/image_error.h), so the two are directly comparable. The pixel value v that stands in for the
/// unknown r is the larger of min(A, B) and the mean of the 8 neighbouring pixels' means, never the pixel's own mean: a
/// rare very bright sample (a caustic firefly) lands in one half, and dividing by the mean that contains it would cap
/// that pixel's term near 1 while its true term is far larger (measured: 0.06x of rel_mse on the glass Cornell box at
/// 16 spp). The half without it is a firefly-free estimate of r, but where bright paths are rare (a caustic at 16-64
/// spp) it is the pixel without them, far below r, and alone overestimated 2.5-3x there. The neighbours hold none of
/// the pixel's samples, so their mean cannot shrink the pixel's own firefly, and between them they have several times
/// its samples of the rare paths. Measured in docs/BENCHMARKS.md ("est_rel_mse against the true rel_mse"). Pixels whose
/// variance is unknown are left out; NaN when no pixel has both halves.
double est_rel_mse(const Film& film);

/// pixel_rel_error of every pixel as a grey image (infinity where unknown).
Image rel_error_image(const Film& film);
/// The samples each pixel received (Film::taken) as a grey image.
Image spp_image(const Film& film);

struct SppSummary {
  uint32_t min = 0, max = 0;
  double mean = 0.0;
};
SppSummary spp_summary(const Film& film);

}  // namespace pt
