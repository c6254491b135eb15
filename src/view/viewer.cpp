/// The window: GLFW + OpenGL 3.3 core + Dear ImGui over a RenderSession. The UI thread only polls events, fetches
/// the latest published frame and draws; every edit goes through ViewerState, which never waits for workers.
#include "view/viewer.h"

#include <glad/gl.h>
// glad must come before GLFW.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <thread>

#include "core/atomic_file.h"
#include "view/camera_control.h"
#include "view/display.h"
#include "view/panels.h"
#include "view/script.h"
#include "view/viewer_state.h"

namespace pt {

namespace {

constexpr int kPanelWidth = 360;

struct Input {
  double scroll = 0.0;
  std::vector<std::string> dropped;
};
Input* g_input = nullptr;  // GLFW callbacks carry no user data besides the window pointer's

/// Runs scripted commands one by one; commands that wait keep their place until satisfied.
struct ScriptRunner {
  std::string file;
  std::vector<ScriptCommand> commands;
  size_t next = 0;
  uint64_t epoch_before_previous = 0, epoch_before_current = 0;
  Clock::time_point wait_until{};
  bool waiting_ms = false;
  int failures = 0;
  bool quit = false;

  bool done() const { return next >= commands.size(); }
};

vec3 parse_triplet(const std::string& s) {
  vec3 v(0.0f);
  std::stringstream in(s);
  std::string part;
  for (int k = 0; k < 3 && std::getline(in, part, ','); ++k) v[k] = std::stof(part);
  return v;
}

/// Executes script commands until one has to wait. Returns false when the program should quit.
void step_script(ScriptRunner& sr, ViewerState& st, std::string& screenshot_request) {
  while (!sr.done()) {
    const ScriptCommand& c = sr.commands[sr.next];
    auto num = [&](size_t i) { return std::stof(c.args[i]); };
    if (c.name == "wait-frames") {
      if (st.loading.valid() || st.frame.epoch != st.session->epoch() || st.frame.frames < int(num(0)))
        return;
    } else if (c.name == "wait-ms") {
      if (!sr.waiting_ms) {
        sr.waiting_ms = true;
        sr.wait_until = Clock::now() + std::chrono::milliseconds(int(num(0)));
        return;
      }
      if (Clock::now() < sr.wait_until) return;
      sr.waiting_ms = false;
    }
    sr.epoch_before_previous = sr.epoch_before_current;
    sr.epoch_before_current = st.session->epoch();
    auto fail = [&](const std::string& why) {
      std::fprintf(stderr, "ptview: %s:%d: %s\n", sr.file.c_str(), c.line, why.c_str());
      ++sr.failures;
    };
    if (c.name == "orbit") {
      orbit_camera(*st.scene.camera, num(0), num(1));
      st.restart();
    } else if (c.name == "pan") {
      pan_camera(*st.scene.camera, num(0), num(1));
      st.restart();
    } else if (c.name == "dolly") {
      dolly_camera(*st.scene.camera, num(0));
      st.restart();
    } else if (c.name == "pick") {
      st.selected_material = st.pick(int(num(0)), int(num(1)));
      if (st.selected_material < 0) fail("pick: no object under that pixel");
    } else if (c.name == "set-material") {
      if (st.selected_material < 0) {
        fail("set-material: nothing picked");
      } else {
        Material& m = st.scene.materials[size_t(st.selected_material)];
        m.type = c.args[0] == "glass" ? MaterialType::glass
                 : c.args[0] == "specular" ? MaterialType::specular : MaterialType::diffuse;
        for (size_t k = 1; k < c.args.size(); ++k) {
          std::string key = c.args[k].substr(0, c.args[k].find('='));
          std::string val = c.args[k].substr(c.args[k].find('=') + 1);
          if (key == "ior") m.ior = std::stof(val);
          else if (key == "albedo") m.albedo = parse_triplet(val);
          else if (key == "emission") m.emission = parse_triplet(val);
        }
        st.restart();
      }
    } else if (c.name == "light-size") {
      if (st.light_quad() < 0) fail("light-size: the scene has no rectangle light");
      else st.set_light_size(num(0), num(1));
    } else if (c.name == "light-intensity") {
      int q = st.light_quad();
      if (q < 0) {
        fail("light-intensity: the scene has no rectangle light");
      } else {
        st.scene.materials[st.scene.quads[size_t(q)].material].emission *= num(0);
        st.restart();
      }
    } else if (c.name == "exposure") {
      st.display.exposure = num(0);
    } else if (c.name == "tonemap") {
      st.display.tonemap = c.args[0] == "aces" ? Tonemap::aces : c.args[0] == "reinhard" ? Tonemap::reinhard : Tonemap::clamp;
    } else if (c.name == "load") {
      st.start_load(c.args[0]);
    } else if (c.name == "screenshot") {
      screenshot_request = c.args[0];
      ++sr.next;
      return;  // taken at the end of this UI frame
    } else if (c.name == "save") {
      st.save_current(c.args[0]);
    } else if (c.name == "expect-restart") {
      if (st.session->epoch() == sr.epoch_before_previous) fail("expected a restart, the epoch did not change");
    } else if (c.name == "expect-no-restart") {
      if (st.session->epoch() != sr.epoch_before_previous) fail("expected no restart, but the epoch changed");
    } else if (c.name == "quit") {
      sr.quit = true;
    }
    ++sr.next;
  }
}

}  // namespace

int run_viewer(const RenderParams& params, const DisplaySettings& display, const ViewerHooks& hooks, Scene scene) {
  ScriptRunner script;
  if (!hooks.script.empty()) {
    Result<std::vector<ScriptCommand>> cmds = load_script(hooks.script);
    if (!cmds) {
      std::fprintf(stderr, "ptview: error: %s\n", cmds.error().c_str());
      return 2;
    }
    script.file = hooks.script;
    script.commands = std::move(*cmds);
  }
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!x11 || !*x11) && (!wayland || !*wayland)) {
    std::fprintf(stderr, "ptview: error: no display to open a window on; render headless with --frames N\n");
    return 2;
  }
  if (!glfwInit()) {
    std::fprintf(stderr, "ptview: error: cannot initialize the window system; render headless with --frames N\n");
    return 2;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
  int win_w = std::min(params.width, 1600) + kPanelWidth, win_h = std::max(std::min(params.height, 1200), 760);
  GLFWwindow* window = glfwCreateWindow(win_w, win_h, "ptview", nullptr, nullptr);
  if (!window) {
    std::fprintf(stderr, "ptview: error: cannot open an OpenGL 3.3 window; render headless with --frames N\n");
    glfwTerminate();
    return 2;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  if (!gladLoadGL(glfwGetProcAddress)) {
    std::fprintf(stderr, "ptview: error: cannot load OpenGL 3.3 functions; render headless with --frames N\n");
    glfwDestroyWindow(window);
    glfwTerminate();
    return 2;
  }
  Input input;
  g_input = &input;
  glfwSetScrollCallback(window, [](GLFWwindow*, double, double y) { g_input->scroll += y; });
  glfwSetDropCallback(window, [](GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i) g_input->dropped.emplace_back(paths[i]);
  });

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini littering the working directory
  float xscale = 1.0f, yscale = 1.0f;
  glfwGetWindowContentScale(window, &xscale, &yscale);
  ImGui::GetStyle().ScaleAllSizes(xscale);
  ImGui::GetIO().FontGlobalScale = xscale;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains our scroll/drop callbacks
  ImGui_ImplOpenGL3_Init("#version 330 core");

  GlDisplay gl;
  if (std::string err = gl.init(); !err.empty()) {
    std::fprintf(stderr, "ptview: error: %s\n", err.c_str());
    return 2;
  }

  ViewerState st;
  st.params = params;
  st.display = display;
  st.hooks = hooks;
  st.home_camera = *scene.camera;
  st.geo = make_render_geometry(scene);
  st.scene = std::move(scene);
  st.session = std::make_unique<RenderSession>(params.threads);
  st.restart();
  PanelState panels;
  panels.save_path = hooks.out.empty() ? "ptview.png" : hooks.out;

  bool dragging[3] = {false, false, false};
  double press_x = 0, press_y = 0, last_x = 0, last_y = 0;
  bool drag_moved = false;
  bool r_was_down = false, f_was_down = false;
  std::vector<uint64_t> shown_epochs;
  int exit_code = 0;
  auto last_frame_time = Clock::now();

  while (!glfwWindowShouldClose(window)) {
    // Wait for input at most one 60 Hz frame: the UI stays responsive without spinning a core the renderer needs
    // (vsync alone does not throttle under Xvfb).
    glfwWaitEventsTimeout(1.0 / 60.0);
    auto now = Clock::now();
    double dt = std::chrono::duration<double>(now - last_frame_time).count();
    last_frame_time = now;
    ImGuiIO& io = ImGui::GetIO();
    int fb_w, fb_h, ww, wh;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    glfwGetWindowSize(window, &ww, &wh);
    const float to_fb = ww > 0 ? float(fb_w) / float(ww) : 1.0f;
    const int panel_px = int(kPanelWidth * xscale * to_fb);
    Rect image_rect = letterbox(std::max(1, fb_w - panel_px), fb_h, st.params.width, st.params.height);
    image_rect.x += panel_px;

    // Background load finished?
    st.poll_load();
    for (const std::string& path : input.dropped) st.start_load(path);
    input.dropped.clear();

    // Mouse: drags in the image area move the camera; a click without motion picks.
    double mx, my;
    glfwGetCursorPos(window, &mx, &my);
    const bool in_image = !io.WantCaptureMouse && mx * to_fb >= panel_px;
    bool camera_moved = false;
    for (int b = 0; b < 3; ++b) {
      bool down = glfwGetMouseButton(window, b) == GLFW_PRESS;
      if (down && !dragging[b] && in_image) {
        dragging[b] = true;
        press_x = last_x = mx;
        press_y = last_y = my;
        drag_moved = false;
      } else if (!down && dragging[b]) {
        dragging[b] = false;
        if (b == 0 && !drag_moved) {
          // Window point -> render pixel through the letterbox.
          double px = (mx * to_fb - image_rect.x) / image_rect.w * st.params.width;
          double py = (my * to_fb - (fb_h - image_rect.y - image_rect.h)) / image_rect.h * st.params.height;
          if (px >= 0 && py >= 0 && px < st.params.width && py < st.params.height) {
            st.selected_material = st.pick(int(px), int(py));
            panels.open_material = true;
          }
        }
      }
    }
    if (dragging[0] || dragging[1] || dragging[2]) {
      double dx = mx - last_x, dy = my - last_y;
      if (std::abs(mx - press_x) + std::abs(my - press_y) > 3) drag_moved = true;
      if (drag_moved && (dx != 0 || dy != 0)) {
        if (dragging[0]) orbit_camera(*st.scene.camera, float(-dx * 0.3), float(dy * 0.3));
        else pan_camera(*st.scene.camera, float(dx / std::max(1, wh)), float(dy / std::max(1, wh)));
        camera_moved = true;
      }
      last_x = mx;
      last_y = my;
    }
    if (input.scroll != 0.0 && !io.WantCaptureMouse) {
      dolly_camera(*st.scene.camera, float(std::pow(0.9, input.scroll)));
      camera_moved = true;
    }
    input.scroll = 0.0;
    if (!io.WantCaptureKeyboard) {
      float speed = float(dt) * 0.5f * std::max(1e-3f, glm::length(st.scene.camera->target - st.scene.camera->eye));
      vec3 move(0.0f);
      if (glfwGetKey(window, GLFW_KEY_W) == GLFW_PRESS) move.z += speed;
      if (glfwGetKey(window, GLFW_KEY_S) == GLFW_PRESS) move.z -= speed;
      if (glfwGetKey(window, GLFW_KEY_D) == GLFW_PRESS) move.x += speed;
      if (glfwGetKey(window, GLFW_KEY_A) == GLFW_PRESS) move.x -= speed;
      if (glfwGetKey(window, GLFW_KEY_E) == GLFW_PRESS) move.y += speed;
      if (glfwGetKey(window, GLFW_KEY_Q) == GLFW_PRESS) move.y -= speed;
      if (move != vec3(0.0f)) {
        fly_camera(*st.scene.camera, move);
        camera_moved = true;
      }
      bool r_down = glfwGetKey(window, GLFW_KEY_R) == GLFW_PRESS, f_down = glfwGetKey(window, GLFW_KEY_F) == GLFW_PRESS;
      bool r_pressed = r_down && !r_was_down, f_pressed = f_down && !f_was_down;
      r_was_down = r_down;
      f_was_down = f_down;
      if (r_pressed) {
        *st.scene.camera = st.home_camera;
        st.restart();
      }
      if (f_pressed) {
        *st.scene.camera = framing_camera(st.scene.bounds());
        st.restart();
      }
    }
    if (camera_moved) st.restart();

    std::string screenshot_request;
    if (!script.done()) step_script(script, st, screenshot_request);

    // Show the newest frame; the first frame of an epoch closes its restart-latency measurement.
    if (st.session->fetch(st.frame)) {
      gl.upload(st.frame.image);
      auto it = st.restart_started.find(st.frame.epoch);
      if (it != st.restart_started.end()) {
        st.restart_latency_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - it->second).count());
        st.restart_started.erase(it);
      }
      if (!st.frame.preview && st.frame.frames > 0 && st.frame.seconds > 0)
        st.full_res_frame_seconds = st.frame.seconds / st.frame.frames;
      if (st.full_res_frame_seconds > 0)  // preview frames should take about 10 ms
        st.preview_div = std::clamp(int(std::ceil(std::sqrt(st.full_res_frame_seconds / 0.010))), 1, 8);
    }

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    draw_panels(st, panels, float(kPanelWidth) * xscale, float(wh));
    ImGui::Render();
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    gl.draw(image_rect.x, image_rect.y, image_rect.w, image_rect.h, st.display);
    glViewport(0, 0, fb_w, fb_h);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++st.ui_frames;

    if (!screenshot_request.empty()) {
      if (auto err = save_framebuffer_png(screenshot_request, fb_w, fb_h)) {
        std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
        exit_code = 2;
      }
    }
    bool quit = script.quit;
    if (hooks.quit_after_frames && script.done() && !st.loading.valid() &&
        st.frame.epoch == st.session->epoch() && st.frame.frames >= *hooks.quit_after_frames)
      quit = true;
    if (quit && !hooks.screenshot.empty()) {
      if (auto err = save_framebuffer_png(hooks.screenshot, fb_w, fb_h)) {
        std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
        exit_code = 2;
      }
    }
    glfwSwapBuffers(window);
    if (quit) break;
  }
  if (!glfwWindowShouldClose(window) && script.done() && !script.quit && !hooks.quit_after_frames) {
    // Closed by the user.
  }
  for (auto& f : st.saves)
    if (f.valid())
      if (auto err = f.get()) {
        std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
        exit_code = 2;
      }
  if (!hooks.stats_json.empty())
    if (auto err = write_file_atomic(hooks.stats_json, st.stats_json())) {
      std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
      exit_code = 2;
    }
  st.session.reset();
  gl.destroy();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  if (exit_code == 0 && script.failures > 0) exit_code = 3;
  return exit_code;
}

}  // namespace pt
