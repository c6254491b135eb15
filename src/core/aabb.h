#pragma once
/// Axis-aligned bounding boxes.
#include "core/math.h"

namespace pt {

/// An axis-aligned box; the default value is empty (lo > hi) so that extending it by anything gives that thing.
struct AABB {
  vec3 lo{kInfinity};
  vec3 hi{-kInfinity};

  static AABB of_point(vec3 p) { return {p, p}; }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void extend(vec3 p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
  void extend(const AABB& b) { lo = glm::min(lo, b.lo); hi = glm::max(hi, b.hi); }
  vec3 extent() const { return hi - lo; }
  vec3 center() const { return 0.5f * (lo + hi); }
  /// Half the surface area: the SAH only needs ratios, and this saves a multiply.
  float half_area() const {
    if (empty()) return 0.0f;
    vec3 e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

inline AABB merge(AABB a, const AABB& b) { a.extend(b); return a; }

/// The box if both corners are finite, else the empty box. BVH builders and refits bound primitives with it, so a
/// primitive with a non-finite coordinate (the loaders reject them; an extreme transform could still make one) is in
/// no node box, never hits, and keeps NaN out of the SAH.
inline AABB finite_or_empty(const AABB& b) { return is_finite(b.lo) && is_finite(b.hi) ? b : AABB{}; }

}  // namespace pt
