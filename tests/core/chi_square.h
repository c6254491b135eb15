#pragma once
// Chi-square goodness-of-fit for sampling routines (the approach of Mitsuba 3's chi2 tests and pbrt-v4's
// sampling_test): histogram the samples over a 2D parametrization of the domain, integrate the claimed density
// over every cell, pool cells with few expected samples, and compute the p-value.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/rng.h"

namespace pt::test {

/// Regularized upper incomplete gamma function Q(a, x) (Numerical Recipes 6.2): the chi-square survival function
/// with 2a degrees of freedom at 2x.
inline double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  double gln = std::lgamma(a);
  if (x < a + 1.0) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1.0;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-15) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
  }
  double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

struct ChiSquareResult {
  double p_value = 0.0;
  double statistic = 0.0;
  int dof = 0;
  double expected_total = 0.0;  ///< integral of the density times the sample count: equals it if the pdf is normalized
  std::string describe() const {
    return "chi2=" + std::to_string(statistic) + " dof=" + std::to_string(dof) + " p=" + std::to_string(p_value);
  }
};

/// Pearson's chi-square of points in [0,1]^2 against `density` over [0,1]^2, on an nx x ny grid: the density is
/// integrated over every cell, and cells expecting fewer than 5 points are pooled into one.
inline ChiSquareResult chi_square_of_points(const std::vector<vec2>& points, const std::function<double(vec2)>& density,
                                            int nx, int ny) {
  std::vector<double> observed(size_t(nx) * ny, 0.0), expected(size_t(nx) * ny, 0.0);
  for (vec2 p : points) {
    int ix = std::clamp(int(p.x * nx), 0, nx - 1), iy = std::clamp(int(p.y * ny), 0, ny - 1);
    observed[size_t(iy) * nx + ix] += 1.0;
  }
  const double n_samples = double(points.size());
  // Integrate the density over each cell with a 16x16 midpoint rule.
  const int sub = 16;
  ChiSquareResult r;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      double sum = 0.0;
      for (int sy = 0; sy < sub; ++sy)
        for (int sx = 0; sx < sub; ++sx) {
          vec2 x((ix + (sx + 0.5f) / sub) / nx, (iy + (sy + 0.5f) / sub) / ny);
          sum += density(x);
        }
      expected[size_t(iy) * nx + ix] = sum / (double(sub) * sub * nx * ny) * n_samples;
      r.expected_total += expected[size_t(iy) * nx + ix];
    }
  // Pool cells expecting fewer than 5 samples into one.
  double pooled_obs = 0.0, pooled_exp = 0.0;
  int cells = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < 5.0) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
      continue;
    }
    r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++cells;
  }
  if (pooled_exp >= 5.0) {
    r.statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++cells;
  } else if (pooled_obs > 0 && pooled_exp == 0.0) {
    r.statistic = 1e30;  // samples where the density says none can be
  }
  r.dof = cells - 1;
  r.p_value = r.dof > 0 ? gamma_q(0.5 * r.dof, 0.5 * r.statistic) : 0.0;
  return r;
}

/// `sample(u)` returns a point in [0,1]^2 (a parametrization of the domain); `density(x)` is the claimed density
/// of that point over [0,1]^2. Returns the p-value of "samples follow the density".
inline ChiSquareResult chi_square_2d(const std::function<vec2(vec2)>& sample, const std::function<double(vec2)>& density,
                                     int nx, int ny, int n_samples, uint64_t seed) {
  std::vector<vec2> points(static_cast<size_t>(n_samples));
  Pcg32 rng(seed, 0x1234);
  for (vec2& p : points) p = sample(vec2(rng.next_float(), rng.next_float()));
  return chi_square_of_points(points, density, nx, ny);
}

}  // namespace pt::test
