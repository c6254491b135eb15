#pragma once
// Small scenes built in code for the render tests.
#include "scene/scene.h"

namespace pt::test {

inline uint32_t add_material(Scene& s, Material m) {
  s.materials.push_back(std::move(m));
  return uint32_t(s.materials.size() - 1);
}

inline Material diffuse(vec3 albedo, vec3 emission = vec3(0.0f)) {
  Material m;
  m.name = "diffuse";
  m.albedo = albedo;
  m.emission = emission;
  return m;
}

inline Material mirror(vec3 albedo) {
  Material m;
  m.name = "mirror";
  m.type = MaterialType::specular;
  m.albedo = albedo;
  return m;
}

/// Every mirror and glass of `s` made diffuse with `albedo` (lights are diffuse and stay): the scene with no delta
/// material, for the diffuse-only path kernel or a low noise floor.
inline void make_diffuse_only(Scene& s, vec3 albedo) {
  for (Material& m : s.materials)
    if (m.type != MaterialType::diffuse) m = diffuse(albedo);
}

/// Axis-aligned box [lo, hi] made of 6 quads whose front faces point inward (or outward).
inline void add_box(Scene& s, vec3 lo, vec3 hi, uint32_t material, bool inward) {
  vec3 d = hi - lo;
  auto quad = [&](vec3 corner, vec3 e1, vec3 e2) {
    if (inward) std::swap(e1, e2);
    s.quads.push_back({corner, e1, e2, material});
  };
  // Outward-facing orientation: cross(e1, e2) points out of the box.
  quad(lo, vec3(0, d.y, 0), vec3(d.x, 0, 0));                       // z = lo.z, normal -z
  quad(vec3(lo.x, lo.y, hi.z), vec3(d.x, 0, 0), vec3(0, d.y, 0));   // z = hi.z, normal +z
  quad(lo, vec3(0, 0, d.z), vec3(0, d.y, 0));                       // x = lo.x, normal -x
  quad(vec3(hi.x, lo.y, lo.z), vec3(0, d.y, 0), vec3(0, 0, d.z));   // x = hi.x, normal +x
  quad(lo, vec3(d.x, 0, 0), vec3(0, 0, d.z));                       // y = lo.y, normal -y
  quad(vec3(lo.x, hi.y, lo.z), vec3(0, 0, d.z), vec3(d.x, 0, 0));   // y = hi.y, normal +y
}

/// A small Cornell-like box with a ceiling light, a glass and a mirror sphere: exercises every material.
inline Scene make_test_cornell() {
  Scene s;
  s.source = "test:cornell";
  uint32_t white = add_material(s, diffuse(vec3(0.7f)));
  uint32_t red = add_material(s, diffuse(vec3(0.6f, 0.1f, 0.1f)));
  uint32_t light = add_material(s, diffuse(vec3(0.0f), vec3(15.0f, 12.0f, 8.0f)));
  Material glass;
  glass.type = MaterialType::glass;
  glass.ior = 1.5f;
  uint32_t g = add_material(s, glass);
  Material mirror;
  mirror.type = MaterialType::specular;
  mirror.albedo = vec3(0.9f);
  uint32_t m = add_material(s, mirror);
  add_box(s, vec3(-1, 0, -1), vec3(1, 2, 1), white, true);
  s.quads[2].material = red;
  s.quads.push_back({vec3(-0.25f, 1.98f, -0.25f), vec3(0.5f, 0, 0), vec3(0, 0, 0.5f), light});
  s.spheres.push_back({vec3(-0.45f, 0.4f, 0.0f), 0.4f, g});
  s.spheres.push_back({vec3(0.45f, 0.4f, -0.3f), 0.4f, m});
  s.camera = Camera{vec3(0, 1, 0.99f), vec3(0, 1, -1), vec3(0, 1, 0), 70.0f};
  return s;
}

}  // namespace pt::test
