#pragma once
// The (0, k, 2)-net property of low-discrepancy points in [0,1)^2, shared by the Sobol tests (core) and the pixel
// sampler's (render).
#include <vector>

#include "core/math.h"

namespace pt::test {

/// True if each elementary interval [i/2^a, (i+1)/2^a) x [j/2^b, (j+1)/2^b), a + b = k, holds exactly one point
/// (so there must be 2^k points).
inline bool is_net(const std::vector<vec2>& pts, int k) {
  if (pts.size() != (size_t(1) << k)) return false;
  for (int a = 0; a <= k; ++a) {
    int b = k - a;
    std::vector<int> count(size_t(1) << k, 0);
    for (vec2 p : pts) {
      int i = int(p.x * float(1 << a)), j = int(p.y * float(1 << b));
      if (i < 0 || i >= (1 << a) || j < 0 || j >= (1 << b)) return false;
      if (++count[size_t(i) * (size_t(1) << b) + size_t(j)] > 1) return false;
    }
  }
  return true;
}

}  // namespace pt::test
