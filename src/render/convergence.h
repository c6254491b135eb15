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
  dvec3 scale;     ///< min(A, B): the pixel value the relative figures divide by (see est_rel_mse)
};
/// Per channel; false when a half is empty (the variance is unknown).
bool pixel_estimate(const Film& film, size_t pixel, PixelEstimate& e);
/// Mean and estimated variance of the mean per channel; false when a half is empty (the variance is unknown).
bool pixel_mean_variance(const Film& film, size_t pixel, dvec3& mean, dvec3& var_mean);

/// The per-pixel relative standard error on luminance, sqrt(Var(mean_L)) / sqrt(min(A_L, B_L)^2 + 0.01): the square
/// root of the pixel's term in est_rel_mse (with luminance for the channels), so a pixel below T adds about T^2 or
/// less to est_rel_mse. (The 0.01 keeps dark pixels from needing an absolute error far below what rel_mse can see.)
/// +infinity when the variance is unknown.
double pixel_rel_error(const Film& film, size_t pixel);

/// Mean over pixels and channels of Var(mean) / (v^2 + 0.01): the normalisation of rel_mse against a reference
/// (compare_images), (x - r)^2 / (r^2 + 0.01), so the two are directly comparable. The pixel value v that stands in
/// for the unknown r is min(A, B), not the mean: a rare very bright sample (a caustic firefly) lands in one half,
/// and dividing by the mean that contains it would cap that pixel's term near 1 while its true term is far larger
/// (measured: the estimate came out at 0.06x of rel_mse on the glass Cornell box at 16 spp). The half without it
/// is a firefly-free estimate of r. Elsewhere min(A, B) is a little below the mean, which errs on the safe side
/// (a slightly larger estimate). Pixels whose variance is unknown are left out; NaN when no pixel has both halves.
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
