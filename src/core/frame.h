#pragma once
/// Orthonormal shading frames.
#include "core/math.h"

namespace pt {

/// An orthonormal basis (s, t, n). Built with the branchless method of Duff et al. 2017, "Building an Orthonormal
/// Basis, Revisited" (JCGT 6(1)), which is continuous and exact everywhere, including n = -z where a rotation
/// from +z breaks down.
struct Frame {
  vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  static Frame from_normal(vec3 n) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    Frame f;
    f.s = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = vec3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
  }
  vec3 to_local(vec3 v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
  vec3 to_world(vec3 v) const { return v.x * s + v.y * t + v.z * n; }
};

}  // namespace pt
