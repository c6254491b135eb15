// Light sampling against its claimed densities (chi-square): rectangle lights by area, sphere lights by cone.
#include <gtest/gtest.h>

#include "../core/chi_square.h"
#include "core/frame.h"
#include "render/light.h"

namespace pt {
namespace {

const double kAlpha = 0.01 / 4;

TEST(LightSampling, RectangleByAreaIsUniformOverTheRectangle) {
  Light l = make_rect_light(vec3(-0.5f, 1, -0.3f), vec3(1.2f, 0, 0), vec3(0, 0.2f, 0.8f), vec3(1));
  vec3 ref(0.1f, -0.5f, 0.2f);
  ASSERT_GT(glm::dot(ref - l.p0, l.n), 0.0f);  // in front of the light
  float l1 = glm::length(l.e1), l2 = glm::length(l.e2);
  auto r = test::chi_square_2d(
      [&](vec2 u) {
        LightSample ls;
        if (!sample_light(l, ref, u, LightSampling::area, ls)) return vec2(-1.0f);
        vec3 p = ls.point.p - l.p0;
        return vec2(glm::dot(p, l.e1) / (l1 * l1), glm::dot(p, l.e2) / (l2 * l2));
      },
      [](vec2) { return 1.0; }, 20, 20, 400000, 21);
  EXPECT_GT(r.p_value, kAlpha) << r.describe();
}

TEST(LightSampling, SphereConeSamplingIsUniformInSolidAngle) {
  for (float dist : {1.5f, 40.0f}) {  // a wide cap, and a narrow one that takes the small-angle branch
    Light l = make_sphere_light(vec3(0, dist, 0), 0.5f, vec3(1));
    vec3 ref(0.0f);
    Frame f = Frame::from_normal(vec3(0, 1, 0));
    double sin2_max = 0.25 / (double(dist) * dist);
    double one_minus_cos_max = 1.0 - std::sqrt(1.0 - sin2_max);
    auto r = test::chi_square_2d(
        [&](vec2 u) {
          LightSample ls;
          if (!sample_light(l, ref, u, LightSampling::solid_angle, ls)) return vec2(-1.0f);
          EXPECT_NEAR(ls.pdf, 1.0 / (2.0 * M_PI * one_minus_cos_max), 2e-3 / one_minus_cos_max);
          EXPECT_NEAR(glm::length(ls.point.p - l.p0), 0.5f, 1e-4f * dist);
          vec3 d = f.to_local(ls.wi);
          double one_minus_cos = double(d.x * d.x + d.y * d.y) / (1.0 + d.z);
          float phi = std::atan2(d.y, d.x);
          if (phi < 0) phi += 2.0f * float(M_PI);
          return vec2(float(std::min(one_minus_cos / one_minus_cos_max, 0.999999)), phi / (2.0f * float(M_PI)));
        },
        [](vec2) { return 1.0; }, 16, 16, 300000, 22);
    EXPECT_GT(r.p_value, kAlpha) << "dist " << dist << " " << r.describe();
  }
}

TEST(LightSampling, BackSideAndBehindGiveNothing) {
  Light rect = make_rect_light(vec3(0, 1, 0), vec3(0, 0, 1), vec3(1, 0, 0), vec3(1));  // faces +y
  LightSample ls;
  EXPECT_FALSE(sample_light(rect, vec3(0.5f, 0.0f, 0.5f), vec2(0.5f), LightSampling::solid_angle, ls));
  EXPECT_EQ(light_pdf(rect, vec3(0.5f, 0.0f, 0.5f), vec3(0, 1, 0), 1.0f, rect.n, LightSampling::solid_angle), 0.0f);
  EXPECT_TRUE(sample_light(rect, vec3(0.5f, 2.0f, 0.5f), vec2(0.5f), LightSampling::solid_angle, ls));
  Light sphere = make_sphere_light(vec3(0), 1.0f, vec3(1));
  EXPECT_FALSE(sample_light(sphere, vec3(0.2f, 0, 0), vec2(0.5f), LightSampling::solid_angle, ls));  // inside
}

}  // namespace
}  // namespace pt
