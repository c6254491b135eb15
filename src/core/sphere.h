#pragma once
/// The one sphere struct. The scene's sphere adds its material (scene/scene.h), the trace geometry's its primitive
/// id (accel/geometry.h); everything geometric (bounds, intersection, light sampling) reads only this part.
#include "core/aabb.h"
#include "core/math.h"

namespace pt {

struct SphereShape {
  vec3 center{0.0f};
  float radius = 1.0f;

  AABB bounds() const { return {center - vec3(radius), center + vec3(radius)}; }
};

}  // namespace pt
