#pragma once
/// Float arctangent, sine and cosine as short inlined polynomials for the sampling warps (core/sampling.cpp).
/// The arctangent serves the solid-angle warps (spherical rectangles and triangles), which need one or two per
/// light sample. The C library's atanf is an out-of-line call with its own reduction and special cases
/// (measured: 4 atanf were about 11 ns of a 100 ns rectangle setup + sample);
/// this one is within about 2 ulp (tests/core/test_fast_trig.cpp bounds it against double precision) and costs one
/// division and a handful of multiplications. Coefficients: Cephes' atanf minimax polynomial on
/// [-tan(pi/8), tan(pi/8)] (S. Moshier, "Methods and Programs for Mathematical Functions", 1989). Sine and cosine
/// of an angle already within [-pi/4, pi/4] (the concentric disk map's, which is every diffuse bounce's) need no
/// reduction at all: fast_sincos_quarter. Where a reduction would be needed (the spherical rectangle's angle) they
/// stay with the C library: glibc's sincosf measured as fast as a polynomial with our own reduction.
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/math.h"

namespace pt {

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

/// sin(x) and cos(x) for |x| <= pi/4, within about 1 ulp (tests/core/test_fast_trig.cpp bounds them against double
/// precision): Cephes' sinf and cosf minimax polynomials on that range (Moshier 1989), the two evaluated side by side
/// from the one square. The C library's sincosf is an out-of-line call that first reduces its argument; on the
/// cosine-weighted bounce it was about 4% of a Cornell frame (issue 11).
inline void fast_sincos_quarter(float x, float& s, float& c) {
  const float z = x * x;
  s = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * x + x;
  c = ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z - 0.5f * z + 1.0f;
}

}  // namespace pt
