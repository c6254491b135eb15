#pragma once
/// The chord ends of a spherical rectangle (core/sampling.cpp; Urena, Fajardo and King 2013, section 4): what the
/// y inversion needs of a chord end y seen from squared distance d2. With r = sqrt(d2 + y^2): the sine y / r, 1 / r,
/// and 1 - y / r and 1 + y / r each without cancellation (the one that would cancel is d2 / (r (r + |y|))), which
/// keeps the inversion exact where the chord is seen nearly end-on. One division, and no branch (the sign of y is
/// random from one receiver to the next).
#include <cmath>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace pt {

struct ChordSine {
  float sine, inv_r, one_minus, one_plus;
};

inline ChordSine chord_sine(float y, float d2) {
  const float a = std::abs(y), r = std::sqrt(d2 + y * y), ra = r + a;
  const float inv = 1.0f / (r * ra);
  const float inv_r = ra * inv, small = d2 * inv, large = ra * ra * inv;  // 1 / r, 1 - |y| / r, 1 + |y| / r
  return {y * inv_r, inv_r, y > 0.0f ? small : large, y > 0.0f ? large : small};
}

/// chord_sine of both ends of a chord at once, bit for bit the same (the same operations, lane by lane): the two
/// square roots and the two divisions share one instruction each. A rectangle's setup and sample make two such
/// pairs, and the divider's throughput, more than the arithmetic, bounds how many rectangle samples a core makes
/// per second (measured: a setup + sample 6% faster; docs/BENCHMARKS.md, twenty-second round).
inline void chord_sines(float ya, float yb, float d2, ChordSine& ea, ChordSine& eb) {
#if defined(__SSE2__)
  const __m128 y = _mm_setr_ps(ya, yb, ya, yb), d = _mm_set1_ps(d2);
  const __m128 a = _mm_andnot_ps(_mm_set1_ps(-0.0f), y);
  const __m128 r = _mm_sqrt_ps(_mm_add_ps(d, _mm_mul_ps(y, y))), ra = _mm_add_ps(r, a);
  const __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), _mm_mul_ps(r, ra));
  const __m128 inv_r = _mm_mul_ps(ra, inv), small = _mm_mul_ps(d, inv), large = _mm_mul_ps(_mm_mul_ps(ra, ra), inv);
  const __m128 sine = _mm_mul_ps(y, inv_r), positive = _mm_cmpgt_ps(y, _mm_setzero_ps());
  const __m128 one_minus = _mm_or_ps(_mm_and_ps(positive, small), _mm_andnot_ps(positive, large));
  const __m128 one_plus = _mm_or_ps(_mm_and_ps(positive, large), _mm_andnot_ps(positive, small));
  alignas(16) float s[4], ir[4], m[4], p[4];
  _mm_store_ps(s, sine);
  _mm_store_ps(ir, inv_r);
  _mm_store_ps(m, one_minus);
  _mm_store_ps(p, one_plus);
  ea = {s[0], ir[0], m[0], p[0]};
  eb = {s[1], ir[1], m[1], p[1]};
#else
  ea = chord_sine(ya, d2);
  eb = chord_sine(yb, d2);
#endif
}

}  // namespace pt
