#include "view/display_mode.h"

#include <algorithm>
#include <cmath>

#include "render/session.h"

namespace pt {

namespace {

float srgb_decode(float s) { return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f); }

vec3 heat_linear(float t) {
  vec3 s = heat_srgb(t);
  return {srgb_decode(s.x), srgb_decode(s.y), srgb_decode(s.z)};
}

float log_position(double v) {
  if (!(v > 0)) return 0.0f;
  double t = (std::log10(v) - std::log10(kRelErrorLo)) / (std::log10(kRelErrorHi) - std::log10(kRelErrorLo));
  return float(std::clamp(t, 0.0, 1.0));
}

const vec3 kUnknown{0.18f};

/// A per-pixel scalar map (first channel of `values`, or `value(i)`) to heat colours.
template <class F>
Image colorize(int w, int h, F&& position) {
  Image out(w, h);
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    float t = position(i);
    vec3 c = t < 0 ? kUnknown : heat_linear(t);
    out.rgb[i * 3] = c.x;
    out.rgb[i * 3 + 1] = c.y;
    out.rgb[i * 3 + 2] = c.z;
  }
  return out;
}

}  // namespace

vec3 heat_srgb(float t) {
  static const vec3 stops[] = {{0.00f, 0.00f, 0.02f}, {0.34f, 0.06f, 0.43f}, {0.73f, 0.21f, 0.33f},
                               {0.98f, 0.55f, 0.04f}, {0.99f, 1.00f, 0.64f}};
  t = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f) * 4.0f;
  int i = std::min(int(t), 3);
  return glm::mix(stops[i], stops[i + 1], t - float(i));
}

bool make_display_image(DisplayMode mode, const SessionFrame& frame, const Image* reference, Image& out,
                        HeatLegend& legend) {
  const int w = frame.image.width, h = frame.image.height;
  const size_t n = size_t(w) * size_t(h);
  auto same_size = [&](const Image& m) { return m.width == w && m.height == h && m.rgb.size() == n * 3; };
  if (mode == DisplayMode::error && !frame.preview && same_size(frame.rel_error)) {
    legend = {"relative error", kRelErrorLo, kRelErrorHi, true};
    out = colorize(w, h, [&](size_t i) {
      double v = frame.rel_error.rgb[i * 3];
      return std::isfinite(v) ? log_position(v) : -1.0f;
    });
    return true;
  }
  if (mode == DisplayMode::samples && !frame.preview && same_size(frame.spp_map)) {
    float hi = 1.0f;
    for (size_t i = 0; i < n; ++i) hi = std::max(hi, frame.spp_map.rgb[i * 3]);
    legend = {"samples per pixel", 0.0, double(hi), false};
    out = colorize(w, h, [&](size_t i) { return frame.spp_map.rgb[i * 3] / hi; });
    return true;
  }
  if (mode == DisplayMode::reference_error && reference && !frame.preview && same_size(*reference)) {
    legend = {"|x - ref| / ref", kRelErrorLo, kRelErrorHi, true};
    out = colorize(w, h, [&](size_t i) {
      double d = 0.0, r = 0.0;
      for (int c = 0; c < 3; ++c) {
        d += std::abs(double(frame.image.rgb[i * 3 + c]) - reference->rgb[i * 3 + c]);
        r += reference->rgb[i * 3 + c];
      }
      return log_position(d / std::max(r, 1e-3));  // summed over channels: |x - ref| / ref of the pixel's total
    });
    return true;
  }
  out = frame.image;
  return false;
}

}  // namespace pt
