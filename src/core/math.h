#pragma once
/// Math aliases and small helpers shared by every layer. GLM supplies the vector types; this header fixes the
/// names the rest of the code uses so a type change happens in one place.
#include <glm/glm.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pt {

using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using dvec3 = glm::dvec3;
using ivec2 = glm::ivec2;
using ivec3 = glm::ivec3;
using uvec3 = glm::uvec3;
using mat3 = glm::mat3;
using mat4 = glm::mat4;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kTwoPi = 6.28318530717958647692f;
inline constexpr float kInv2Pi = 0.15915494309189533577f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
/// Largest float below 1: where samples in [0,1) are clamped to.
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

inline float max_component(vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }
inline float min_component(vec3 v) { return std::min(v.x, std::min(v.y, v.z)); }
inline int max_dimension(vec3 v) { return v.x > v.y ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2); }
/// Rec. 709 luminance, used for light power and Russian roulette.
inline float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
/// The same in double, for the film's sums (the adaptive sampler's per-pixel error).
inline double luminance(dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
inline bool is_finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool is_black(vec3 v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; }
/// Whether two edges meet at a right angle, to a relative 1e-5 (a quad light that passes is a rectangle: spherical
/// rectangle sampling in render/light.cpp, "rectangle" in the Light panel).
inline bool at_right_angle(vec3 a, vec3 b) {
  return std::abs(glm::dot(a, b)) <= 1e-5f * glm::length(a) * glm::length(b);
}
template <class T> inline T sqr(T x) { return x * x; }
/// sqrt that returns 0 for the tiny negative arguments rounding produces.
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
inline float safe_asin(float x) { return std::asin(std::clamp(x, -1.0f, 1.0f)); }
inline float safe_acos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

/// Bound on the relative rounding error of n chained float operations (pbrt-v4, section 6.8.1).
inline constexpr float gamma_bound(int n) {
  constexpr float eps = std::numeric_limits<float>::epsilon() * 0.5f;
  return (n * eps) / (1 - n * eps);
}

inline float next_float_up(float v) {
  if (std::isinf(v) && v > 0.0f) return v;
  if (v == -0.0f) v = 0.0f;
  uint32_t ui = std::bit_cast<uint32_t>(v);
  ui = v >= 0 ? ui + 1 : ui - 1;
  return std::bit_cast<float>(ui);
}
inline float next_float_down(float v) {
  if (std::isinf(v) && v < 0.0f) return v;
  if (v == 0.0f) v = -0.0f;
  uint32_t ui = std::bit_cast<uint32_t>(v);
  ui = v > 0 ? ui - 1 : ui + 1;
  return std::bit_cast<float>(ui);
}

}  // namespace pt
