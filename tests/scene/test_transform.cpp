// scene/transform.h on its own: apply_transform maps world positions by the affine map, whatever the mesh's origin
// already is, and turns shading normals by the inverse transpose, leaving an unusable (zero) normal zero, never NaN.
#include <gtest/gtest.h>

#include "scene/transform.h"

namespace pt {
namespace {

Mesh two_triangles(dvec3 origin) {
  Mesh m;
  m.origin = origin;
  m.positions = {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0), vec3(0.5f, -2, 4)};
  m.indices = {uvec3(0, 1, 2), uvec3(1, 3, 2)};
  m.normals = {vec3(0, 0, 1), vec3(0, 0, 0), vec3(3, 0, 4)};
  m.normal_indices = {uvec3(0, 2, 0), uvec3(1, 0, 2)};
  return m;
}

TEST(Transform, WorldPositionsMoveByTheAffineMapWhateverTheOrigin) {
  const Transform t = make_transform(vec3(2, 1, 0.5f), vec3(1, 2, 3), 70.0f, vec3(1, -2, 3));
  for (dvec3 origin : {dvec3(0.0), dvec3(10, -2, 3), dvec3(1e5, 0, -1e5)}) {
    Mesh m = two_triangles(origin);
    std::vector<dvec3> expected;
    for (const vec3& p : m.positions) expected.push_back(t.linear * (origin + dvec3(p)) + t.translation);
    apply_transform(m, t);
    for (size_t i = 0; i < expected.size(); ++i) {
      const dvec3 got = m.origin + dvec3(m.positions[i]);
      EXPECT_LT(glm::length(got - expected[i]), 1e-6 * (1.0 + glm::length(expected[i] - m.origin)))
          << "vertex " << i << " of a mesh with origin " << origin.x;
    }
  }
}

TEST(Transform, NormalsTurnByTheInverseTransposeAndAZeroNormalStaysZero) {
  const Transform t = make_transform(vec3(1, 1, 4), vec3(0, 1, 0), 90.0f, vec3(0.0f));
  Mesh m = two_triangles(dvec3(0.0));
  apply_transform(m, t);
  // The inverse transpose of (rotation * scale) is rotation * scale^-1: (0, 0, 1) -> (0, 0, 1/4) -> turned about y
  // to (1/4, 0, 0), normalized (1, 0, 0).
  EXPECT_LT(glm::length(m.normals[0] - vec3(1, 0, 0)), 1e-6f);
  EXPECT_EQ(m.normals[1], vec3(0.0f));  // "vn 0 0 0" in a file: no usable direction, and no NaN from 0 / 0
  EXPECT_NEAR(glm::length(m.normals[2]), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace pt
