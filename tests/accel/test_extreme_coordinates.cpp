// Found by fuzz_render (issue 18): triangles near 1e30 got a NaN geometric normal (their edge cross product
// overflows), so a bounce ray got a NaN direction. In the 8-wide node test every distance of such a ray is NaN, and
// a NaN distance leaves the slab interval open (as it must for 0 * inf on a slab plane), so the unused slots of a
// node (empty boxes) were "hit" too and the traversal read a leaf at the empty-slot reference: a crash. Any ray,
// even a NaN one, must traverse safely.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/geometry.h"
#include "core/rng.h"

namespace pt {
namespace {

TEST(ExtremeCoordinates, NonFiniteRaysTraverseSafely) {
  // A few triangles (so nodes have unused slots), at ordinary and at huge coordinates.
  for (float scale : {1.0f, 1e30f}) {
    std::vector<vec3> v;
    Pcg32 rng(7, 1);
    auto coord = [&] { return (rng.next_float() * 2.0f - 1.0f) * scale; };
    for (int t = 0; t < 21; ++t) {
      vec3 c(coord(), coord(), coord());
      v.insert(v.end(), {c, c + vec3(0.1f * scale, 0, 0), c + vec3(0, 0.1f * scale, 0)});
    }
    TraceGeometry g = make_trace_geometry(v, {});
    const float nan = std::nanf(""), inf = kInfinity;
    const vec3 dirs[] = {vec3(nan), vec3(nan, 0, 1), vec3(0.0f), vec3(inf, 0, 0), vec3(inf, -inf, nan), vec3(0, 0, 1)};
    const vec3 origins[] = {vec3(0.0f), vec3(nan), vec3(inf), vec3(3e38f, -3e38f, 3e38f)};
    for (vec3 o : origins)
      for (vec3 d : dirs) {
        Ray ray{o, d, kInfinity};
        Hit hit;
        if (intersect_closest(g, ray, hit)) {
          EXPECT_LT(hit.prim, 21u);
        }
        (void)intersect_any(g, Ray{o, d, kInfinity});
      }
  }
}

}  // namespace
}  // namespace pt
