#include "view/input.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>

#include "view/camera_control.h"

namespace pt {

ImageArea image_area(int fb_w, int fb_h, int win_w, float panel_w, int render_w, int render_h) {
  ImageArea area;
  area.to_fb = win_w > 0 ? float(fb_w) / float(win_w) : 1.0f;
  area.panel_px = int(panel_w * area.to_fb);
  area.fb_height = fb_h;
  area.empty = fb_w - area.panel_px < 1 || fb_h < 1;
  area.w = std::max(1, fb_w - area.panel_px);
  area.h = std::max(1, fb_h);
  area.rect = letterbox(area.w, area.h, render_w, render_h);
  area.rect.x += area.panel_px;
  return area;
}

ivec2 followed_size(const ImageArea& area) { return {std::min(area.w, 16384), std::min(area.h, 16384)}; }

std::optional<ivec2> SizeFollower::update(const ImageArea& area, bool locked, ivec2 render, double now_seconds) {
  if (!follows_area(area, locked)) return std::nullopt;
  const ivec2 size = followed_size(area);
  if (size != want) {
    want = size;
    since = now_seconds;
    return std::nullopt;
  }
  if (want == render || now_seconds - since < debounce) return std::nullopt;
  return want;
}

std::optional<ivec2> render_pixel_at(const ImageArea& area, double mx, double my, int render_w, int render_h) {
  const Rect& r = area.rect;
  if (r.w <= 0 || r.h <= 0) return std::nullopt;
  // Window units -> framebuffer pixels (top-left origin) -> the rectangle, whose GL y counts from the bottom.
  const double px = (mx * area.to_fb - r.x) / r.w * render_w;
  const double py = (my * area.to_fb - (area.fb_height - r.y - r.h)) / r.h * render_h;
  if (!(px >= 0 && py >= 0 && px < render_w && py < render_h)) return std::nullopt;
  return ivec2(int(px), int(py));
}

double divider_window_x(const ImageArea& area, float divider) {
  return (area.rect.x + double(divider) * area.rect.w) / area.to_fb;
}

float divider_at(const ImageArea& area, double mx) {
  return area.rect.w > 0 ? float((mx * area.to_fb - area.rect.x) / area.rect.w) : 0.5f;
}

bool grabs_divider(const ImageArea& area, float divider, double mx) {
  return std::abs(mx - divider_window_x(area, divider)) <= 6.0;
}

bool drag_divider(GLFWwindow* window, ViewerState& st, const ImageArea& area, bool ui_mouse, bool& dragging) {
  if (!st.compare) return dragging = false;
  if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) != GLFW_PRESS) return dragging = false;
  double mx, my;
  glfwGetCursorPos(window, &mx, &my);
  if (!dragging && !ui_mouse && grabs_divider(area, st.divider, mx)) dragging = true;
  if (dragging && area.rect.w > 0) st.apply(DividerEdit{divider_at(area, mx)});
  return dragging;
}

bool process_input(GLFWwindow* window, InputState& in, ViewerState& st, const ImageArea& area, double dt,
                   bool ui_mouse, bool ui_keyboard) {
  for (const std::string& path : in.dropped) st.start_load(path);
  in.dropped.clear();
  int ww, wh;
  glfwGetWindowSize(window, &ww, &wh);
  double mx, my;
  glfwGetCursorPos(window, &mx, &my);
  const bool in_image = !ui_mouse && mx * area.to_fb >= area.panel_px;
  Camera cam = st.scene.camera.value_or(Camera{});
  bool camera_moved = false, picked = false;
  for (int b = 0; b < 3; ++b) {
    bool down = glfwGetMouseButton(window, b) == GLFW_PRESS;
    if (down && !in.dragging[b] && in_image) {
      in.dragging[b] = true;
      in.press_x = in.last_x = mx;
      in.press_y = in.last_y = my;
      in.drag_moved = false;
    } else if (!down && in.dragging[b]) {
      in.dragging[b] = false;
      if (b == 0 && !in.drag_moved) {
        if (const std::optional<ivec2> pixel = render_pixel_at(area, mx, my, st.params.width, st.params.height)) {
          st.select_at(pixel->x, pixel->y);
          picked = true;
        }
      }
    }
  }
  if (in.dragging[0] || in.dragging[1] || in.dragging[2]) {
    double dx = mx - in.last_x, dy = my - in.last_y;
    if (std::abs(mx - in.press_x) + std::abs(my - in.press_y) > 3) in.drag_moved = true;
    if (in.drag_moved && (dx != 0 || dy != 0)) {
      if (in.dragging[0]) orbit_camera(cam, float(-dx * 0.3), float(dy * 0.3));
      else pan_camera(cam, float(dx / std::max(1, wh)), float(dy / std::max(1, wh)));
      camera_moved = true;
    }
    in.last_x = mx;
    in.last_y = my;
  }
  if (in.scroll != 0.0 && !ui_mouse) {
    dolly_camera(cam, float(std::pow(0.9, in.scroll)), camera_min_distance(st.geo.get()));
    camera_moved = true;
  }
  in.scroll = 0.0;
  if (!ui_keyboard) {
    float speed = float(dt) * 0.5f * std::max(camera_min_distance(st.geo.get()), camera_distance(cam));
    vec3 move(0.0f);
    if (glfwGetKey(window, GLFW_KEY_W) == GLFW_PRESS) move.z += speed;
    if (glfwGetKey(window, GLFW_KEY_S) == GLFW_PRESS) move.z -= speed;
    if (glfwGetKey(window, GLFW_KEY_D) == GLFW_PRESS) move.x += speed;
    if (glfwGetKey(window, GLFW_KEY_A) == GLFW_PRESS) move.x -= speed;
    if (glfwGetKey(window, GLFW_KEY_E) == GLFW_PRESS) move.y += speed;
    if (glfwGetKey(window, GLFW_KEY_Q) == GLFW_PRESS) move.y -= speed;
    if (move != vec3(0.0f)) {
      fly_camera(cam, move);
      camera_moved = true;
    }
    bool r_down = glfwGetKey(window, GLFW_KEY_R) == GLFW_PRESS, f_down = glfwGetKey(window, GLFW_KEY_F) == GLFW_PRESS;
    if (r_down && !in.r_was_down) {
      cam = st.home_camera;
      camera_moved = true;
    }
    if (f_down && !in.f_was_down) {
      cam = framing_camera(st.scene.bounds());
      camera_moved = true;
    }
    in.r_was_down = r_down;
    in.f_was_down = f_down;
  }
  if (camera_moved) st.apply(CameraEdit{cam});
  return picked;
}

}  // namespace pt
