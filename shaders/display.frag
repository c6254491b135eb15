#version 330 core
// Linear radiance -> exposure -> tonemap -> sRGB. Same formulas as apply_tonemap / srgb_encode in
// src/render/image.cpp, so the window shows what a saved PNG holds.
in vec2 v_uv;
out vec4 frag_color;
uniform sampler2D u_image;
uniform float u_exposure;  // stops
uniform int u_tonemap;     // 0 clamp, 1 Reinhard, 2 ACES (Narkowicz 2015)

vec3 aces(vec3 x) {
  const float a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
  return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}
float srgb(float x) {
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
  vec3 c = max(texture(u_image, v_uv).rgb, vec3(0.0)) * exp2(u_exposure);
  if (u_tonemap == 1) c = c / (1.0 + c);
  else if (u_tonemap == 2) c = aces(c);
  c = clamp(c, 0.0, 1.0);
  frag_color = vec4(srgb(c.r), srgb(c.g), srgb(c.b), 1.0);
}
