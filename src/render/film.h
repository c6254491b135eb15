#pragma once
/// The accumulation buffer: per-pixel sums of samples and their counts, divided only when an image is read.
/// Sums are double so that millions of samples add without losing the small ones.
///
/// Next to the sum the film keeps a second accumulator over one half of the samples (the "A" half, chosen by
/// sample index, see sample_in_half_a). The difference of the two half means estimates the variance of the pixel
/// mean (render/convergence.h), which drives the error estimate and adaptive sampling.
///
/// Every accumulation buffer is a plain vector that adds element-wise: for_each_buffer lists them all, so a
/// reducer (MPI, tests) can sum two films without knowing the buffers' names.
#include <cstdint>
#include <span>
#include <vector>

#include "render/image.h"

namespace pt {

/// Whether sample `index` of a pixel goes to the A half: the even indices. Unbiased with both samplers: the split
/// depends on the index alone, never on the sample values, so each half's mean is an unbiased estimate of the pixel.
/// For (A - B)^2 / 4 to estimate Var(mean) the halves must also be independent: true for independent samples, and
/// made true for Owen-scrambled Sobol by scrambling the even and the odd samples independently (render/sampler.h),
/// as randomized QMC estimates its error from independent replicates (Owen 1997). We measured the alternative of
/// one sequence split into stratification classes (Christensen et al. 2018, section 10.2.1, as Cycles does): its
/// halves are negatively correlated and the estimate came out 1.6x (Cornell box) to 9x (plane under a light) too
/// large (docs/BENCHMARKS.md, "Convergence").
inline bool sample_in_half_a(uint64_t index) { return (index & 1u) == 0; }

struct Film {
  int width = 0;
  int height = 0;
  std::vector<double> sum;          ///< 3 per pixel
  std::vector<uint32_t> count;      ///< finite samples per pixel
  std::vector<double> half_sum;     ///< 3 per pixel: the finite samples of the A half
  std::vector<uint32_t> half_count; ///< finite samples of the A half per pixel
  std::vector<uint32_t> taken;      ///< samples drawn per pixel, finite or not: the next sample index (adaptive)

  Film() = default;
  Film(int w, int h) { reset(w, h); }
  size_t pixel_count() const { return size_t(width) * size_t(height); }
  void reset(int w, int h) {
    width = w;
    height = h;
    const size_t n = size_t(w) * size_t(h);
    sum.assign(n * 3, 0.0);
    count.assign(n, 0);
    half_sum.assign(n * 3, 0.0);
    half_count.assign(n, 0);
    taken.assign(n, 0);
  }
  void clear() { reset(width, height); }
  /// A finite sample with index `sample_index` of `pixel`. (Non-finite ones only call note_taken.)
  void add(size_t pixel, vec3 c, uint64_t sample_index = 0) {
    sum[3 * pixel] += c.x;
    sum[3 * pixel + 1] += c.y;
    sum[3 * pixel + 2] += c.z;
    ++count[pixel];
    if (sample_in_half_a(sample_index)) {
      half_sum[3 * pixel] += c.x;
      half_sum[3 * pixel + 1] += c.y;
      half_sum[3 * pixel + 2] += c.z;
      ++half_count[pixel];
    }
  }
  void note_taken(size_t pixel) { ++taken[pixel]; }
  vec3 mean(size_t pixel) const {
    if (count[pixel] == 0) return vec3(0.0f);
    double inv = 1.0 / count[pixel];
    return vec3(float(sum[3 * pixel] * inv), float(sum[3 * pixel + 1] * inv), float(sum[3 * pixel + 2] * inv));
  }
  /// The mean of the samples so far, the image every output writes.
  Image resolve() const {
    Image img(width, height);
    for (size_t p = 0; p < pixel_count(); ++p) {
      vec3 m = mean(p);
      img.rgb[3 * p] = m.x;
      img.rgb[3 * p + 1] = m.y;
      img.rgb[3 * p + 2] = m.z;
    }
    return img;
  }
  /// Calls f(span) for every accumulation buffer (double and uint32_t spans), always in the same order. Summing
  /// every buffer of two films element-wise gives the film of both sample sets (same size, disjoint samples).
  template <class F>
  void for_each_buffer(F&& f) {
    f(std::span<double>(sum));
    f(std::span<uint32_t>(count));
    f(std::span<double>(half_sum));
    f(std::span<uint32_t>(half_count));
    f(std::span<uint32_t>(taken));
  }
};

}  // namespace pt
