#pragma once
/// Float sine, cosine and arctangent as short inlined polynomials, for the solid-angle warps (spherical rectangles
/// and triangles, core/sampling.cpp), which call them once or twice per light sample. The C library's sinf/atanf
/// are correctly rounded but are out-of-line calls with their own range reduction and special-case branches; these
/// are within a few ulp (tests/core/test_fast_trig.cpp bounds them against double precision) and cost a handful of
/// multiplications. Coefficients: Cephes' sinf, cosf and atanf minimax polynomials (S. Moshier, "Methods and
/// Programs for Mathematical Functions", 1989), on [-pi/4, pi/4] and [-tan(pi/8), tan(pi/8)].
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/math.h"

namespace pt {

struct SinCos {
  float sin, cos;
};

/// sin and cos of x, for |x| <= 8192 (the reduction by pi/2 is a three-part Cody-Waite subtraction, exact for
/// quadrant numbers below 2^14; the warps call it with |x| < 2 pi). Absolute error below 1.2e-7 and relative
/// error a few ulp near the zeros, as the test checks.
inline SinCos fast_sincos(float x) {
  // pi/2 = kA + kB + kC, kA and kB short enough that j * kA and j * kB are exact for |j| < 2^14.
  constexpr float kA = 1.5703125f, kB = 4.837512969970703125e-4f, kC = 7.54978995489188216e-8f;
  const float j = std::nearbyint(x * 0.636619772367581343f);
  const float r = ((x - j * kA) - j * kB) - j * kC;
  const float z = r * r;
  const float s = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * r + r;
  const float c = ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z -
                  0.5f * z + 1.0f;
  // Quadrant j: (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s). Selects and sign flips rather than a switch: j
  // is random in the warps, so a jump would be mispredicted half the time.
  const uint32_t q = uint32_t(int(j));
  const bool swap = (q & 1u) != 0;
  const float sin_abs = swap ? c : s, cos_abs = swap ? s : c;
  const uint32_t sin_sign = (q & 2u) << 30, cos_sign = ((q + 1u) & 2u) << 30;
  return {std::bit_cast<float>(std::bit_cast<uint32_t>(sin_abs) ^ sin_sign),
          std::bit_cast<float>(std::bit_cast<uint32_t>(cos_abs) ^ cos_sign)};
}

/// An angle as quarter * pi/2 + rest with |rest| <= pi/4. Sums of such angles add their quarters as integers, so a
/// small difference of angles near a multiple of pi/2 keeps the relative precision of its small parts.
struct SplitAngle {
  int quarter;
  float rest;
};

/// atan(n / d) for |n| <= |d|, d != 0: one division (Cephes' reduction by pi/4 is folded into the quotient).
inline float fast_atan_ratio(float n, float d) {
  const float an = std::abs(n), ad = std::abs(d);
  const bool reduce = an > 0.414213562373095049f * ad;  // tan(pi/8)
  const float x = (reduce ? an - ad : an) / (reduce ? an + ad : ad);
  const float z = x * x;
  const float p = (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) *
                      z * x + x;
  const float a = (reduce ? 0.785398163397448310f : 0.0f) + p;
  const uint32_t sign = (std::bit_cast<uint32_t>(n) ^ std::bit_cast<uint32_t>(d)) & 0x80000000u;
  return std::bit_cast<float>(std::bit_cast<uint32_t>(a) ^ sign);
}

/// atan2(p, q) for (p, q) != (0, 0), split into quarters (the full circle: quarter in -2..2).
inline SplitAngle split_atan2(float p, float q) {
  const bool steep = std::abs(p) > std::abs(q);  // then atan2 = sign(p) pi/2 - atan(q / p)
  const float rest = fast_atan_ratio(steep ? q : p, steep ? p : q);
  const int flat_quarter = q > 0.0f ? 0 : (std::signbit(p) ? -2 : 2);
  return {steep ? (p > 0.0f ? 1 : -1) : flat_quarter, steep ? -rest : rest};
}

}  // namespace pt
