#pragma once
/// The accumulation buffer: per-pixel sums of samples and their counts, divided only when an image is read.
/// Sums are double so that millions of samples add without losing the small ones.
#include <cstdint>
#include <span>
#include <vector>

#include "render/image.h"

namespace pt {

struct Film {
  int width = 0;
  int height = 0;
  std::vector<double> sum;        ///< 3 per pixel
  std::vector<uint32_t> count;    ///< finite samples per pixel

  Film() = default;
  Film(int w, int h) { reset(w, h); }
  void reset(int w, int h) {
    width = w;
    height = h;
    sum.assign(size_t(w) * size_t(h) * 3, 0.0);
    count.assign(size_t(w) * size_t(h), 0);
  }
  void clear() { reset(width, height); }
  /// Calls f(std::span<T>) for every per-pixel buffer that adds up over samples, always in the same order. A
  /// distributed render (src/dist) sums exactly these buffers across processes in one loop, so a buffer added here
  /// is reduced too.
  template <class F>
  void for_each_sum_buffer(F&& f) {
    f(std::span<double>(sum));
    f(std::span<uint32_t>(count));
  }
  void add(size_t pixel, vec3 c) {
    sum[3 * pixel] += c.x;
    sum[3 * pixel + 1] += c.y;
    sum[3 * pixel + 2] += c.z;
    ++count[pixel];
  }
  vec3 mean(size_t pixel) const {
    if (count[pixel] == 0) return vec3(0.0f);
    double inv = 1.0 / count[pixel];
    return vec3(float(sum[3 * pixel] * inv), float(sum[3 * pixel + 1] * inv), float(sum[3 * pixel + 2] * inv));
  }
  /// The mean of the samples so far, the image every output writes.
  Image resolve() const {
    Image img(width, height);
    for (size_t p = 0; p < size_t(width) * size_t(height); ++p) {
      vec3 m = mean(p);
      img.rgb[3 * p] = m.x;
      img.rgb[3 * p + 1] = m.y;
      img.rgb[3 * p + 2] = m.z;
    }
    return img;
  }
};

}  // namespace pt
