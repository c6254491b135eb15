#include "render/convergence.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/image_error.h"

namespace pt {

namespace {

dvec3 pixel_mean(const Film& film, size_t p) {
  const double n = film.count[p];
  return n > 0 ? dvec3(film.sum[3 * p], film.sum[3 * p + 1], film.sum[3 * p + 2]) / n : dvec3(0.0);
}

/// The mean of the pixel means of p's (up to) 8 neighbours that have samples: an estimate of p's value that does
/// not contain any of p's own samples (see est_rel_mse in the header for why).
dvec3 neighbour_mean(const Film& film, size_t p) {
  const int w = film.width, h = film.height, x = int(p % size_t(w)), y = int(p / size_t(w));
  dvec3 total(0.0);
  int k = 0;
  for (int yy = std::max(y - 1, 0); yy <= std::min(y + 1, h - 1); ++yy)
    for (int xx = std::max(x - 1, 0); xx <= std::min(x + 1, w - 1); ++xx) {
      const size_t q = size_t(yy) * size_t(w) + size_t(xx);
      if (q == p || film.count[q] == 0) continue;
      total += pixel_mean(film, q);
      ++k;
    }
  return k ? total / double(k) : dvec3(0.0);
}

}  // namespace

bool pixel_estimate(const Film& film, size_t p, PixelEstimate& e) {
  const double n = film.count[p], na = film.half_count[p], nb = n - na;
  e.mean = pixel_mean(film, p);
  if (na == 0 || nb == 0) {
    e.var_mean = dvec3(0.0);
    e.scale = e.mean;
    return false;
  }
  const dvec3 s(film.sum[3 * p], film.sum[3 * p + 1], film.sum[3 * p + 2]);
  const dvec3 sa(film.half_sum[3 * p], film.half_sum[3 * p + 1], film.half_sum[3 * p + 2]);
  const dvec3 a = sa / na, b = (s - sa) / nb, d = a - b;
  e.var_mean = d * d * (na * nb / (n * n));
  e.scale = glm::max(glm::min(a, b), neighbour_mean(film, p));
  return true;
}

bool pixel_mean_variance(const Film& film, size_t p, dvec3& mean, dvec3& var_mean) {
  PixelEstimate e;
  bool known = pixel_estimate(film, p, e);
  mean = e.mean;
  var_mean = e.var_mean;
  return known;
}

double pixel_rel_error(const Film& film, size_t p) {
  const double n = film.count[p], na = film.half_count[p], nb = n - na;
  if (na == 0 || nb == 0) return std::numeric_limits<double>::infinity();
  const dvec3 s(film.sum[3 * p], film.sum[3 * p + 1], film.sum[3 * p + 2]);
  const dvec3 sa(film.half_sum[3 * p], film.half_sum[3 * p + 1], film.half_sum[3 * p + 2]);
  const double la = luminance(sa) / na, lb = luminance(s - sa) / nb, d = la - lb, m = std::min(la, lb);
  return std::sqrt(d * d * (na * nb / (n * n)) / (m * m + kRelMseFloor));
}

double est_rel_mse(const Film& film) {
  double total = 0.0;
  size_t pixels = 0;
  for (size_t p = 0; p < film.pixel_count(); ++p) {
    PixelEstimate e;
    if (!pixel_estimate(film, p, e)) continue;
    const dvec3 v = e.var_mean, m = e.scale;
    total += v.x / (m.x * m.x + kRelMseFloor) + v.y / (m.y * m.y + kRelMseFloor) + v.z / (m.z * m.z + kRelMseFloor);
    ++pixels;
  }
  return pixels ? total / (3.0 * double(pixels)) : std::numeric_limits<double>::quiet_NaN();
}

Image rel_error_image(const Film& film) {
  Image img(film.width, film.height);
  for (size_t p = 0; p < film.pixel_count(); ++p) {
    float e = float(pixel_rel_error(film, p));
    img.rgb[3 * p] = img.rgb[3 * p + 1] = img.rgb[3 * p + 2] = e;
  }
  return img;
}

Image spp_image(const Film& film) {
  Image img(film.width, film.height);
  for (size_t p = 0; p < film.pixel_count(); ++p)
    img.rgb[3 * p] = img.rgb[3 * p + 1] = img.rgb[3 * p + 2] = float(film.taken[p]);
  return img;
}

SppSummary spp_summary(const Film& film) {
  SppSummary s;
  if (film.taken.empty()) return s;
  auto [lo, hi] = std::minmax_element(film.taken.begin(), film.taken.end());
  s.min = *lo;
  s.max = *hi;
  double total = 0.0;
  for (uint32_t t : film.taken) total += t;
  s.mean = total / double(film.taken.size());
  return s;
}

}  // namespace pt
