/// The window: GLFW + OpenGL 3.3 core + Dear ImGui over a RenderSession. The UI thread only polls events, turns
/// input into edits (input.cpp, panels.cpp, script.cpp), fetches the latest published frame and draws; every edit
/// goes through ViewerState::apply, which never waits for workers.
#include "view/viewer.h"

#include <glad/gl.h>
// glad must come before GLFW.
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdio>
#include <cmath>
#include <cstdlib>

#include "core/atomic_file.h"
#include "view/display.h"
#include "view/display_mode.h"
#include "view/input.h"
#include "view/panels.h"
#include "view/script.h"
#include "view/viewer_state.h"

namespace pt {

namespace {

constexpr int kPanelWidth = 360;

InputState* g_input = nullptr;  // GLFW callbacks carry no user data besides the window pointer's

/// Creates the window and GL context; null (with the message printed) on failure.
GLFWwindow* open_window(const RenderParams& params) {
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!x11 || !*x11) && (!wayland || !*wayland)) {
    std::fprintf(stderr, "ptview: error: no display to open a window on; render headless with --frames N\n");
    return nullptr;
  }
  if (!glfwInit()) {
    std::fprintf(stderr, "ptview: error: cannot initialize the window system; render headless with --frames N\n");
    return nullptr;
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
    return nullptr;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  if (!gladLoadGL(glfwGetProcAddress)) {
    std::fprintf(stderr, "ptview: error: cannot load OpenGL 3.3 functions; render headless with --frames N\n");
    glfwDestroyWindow(window);
    glfwTerminate();
    return nullptr;
  }
  return window;
}

/// Sets up Dear ImGui for the window; returns the content scale (HiDPI).
float init_imgui(GLFWwindow* window) {
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
  return xscale;
}

void close_window(GLFWwindow* window) {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
}

/// Shows the newest frame; the first frame of an epoch closes its restart-latency measurement, and full frames
/// tune the preview divisor so a preview takes about 10 ms.
void fetch_frame(ViewerState& st, GlDisplay& gl, Image& shown, HeatLegend& legend, bool& heat) {
  const bool fresh = st.fetch_frame();
  if (fresh || st.display_dirty) {
    heat = make_display_image(st.display_mode, st.frame, st.reference ? &*st.reference : nullptr, shown, legend);
    gl.upload(shown);
    st.display_dirty = false;
  }
  if (!fresh) return;
  auto it = st.restart_started.find(st.frame.epoch);
  if (it != st.restart_started.end()) {
    st.restart_latency_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - it->second).count());
    st.restart_started.erase(it);
  }
  if (!st.frame.preview && st.frame.frames > 0 && st.frame.seconds > 0)
    st.full_res_frame_seconds = st.frame.seconds / st.frame.frames;
  if (st.full_res_frame_seconds > 0)
    st.preview_div = std::clamp(int(std::ceil(std::sqrt(st.full_res_frame_seconds / 0.010))), 1, 8);
}

/// B's side of a compare: its newest frame, shown through its own texture.
void fetch_frame_b(ViewerState& st, GlDisplay& gl, Image& shown, bool& heat, bool dirty) {
  if (!st.compare || !st.session_b) return;
  const bool fresh = st.fetch_frame_b();
  if (fresh || dirty) {
    HeatLegend unused;
    heat = make_display_image(st.display_mode, st.frame_b, st.reference ? &*st.reference : nullptr, shown, unused);
    gl.upload(shown);
  }
}

/// The heatmap's legend: a colour bar with values at the bottom right of the image area, right of the panels
/// (usually in the letterbox margin below the image; ImGui coordinates).
void draw_legend(const HeatLegend& legend, float area_x0, float x1, float y1) {
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  const float pad = 8.0f, margin = 24.0f, h = 14.0f;
  const float w = std::clamp(x1 - area_x0 - 2 * margin - 2 * pad, 60.0f, 260.0f);
  const float x0 = x1 - margin - pad - w, y0 = y1 - h - 36.0f;
  dl->AddRectFilled(ImVec2(x0 - pad, y0 - 22.0f), ImVec2(x0 + w + pad, y1 - 6.0f), IM_COL32(0, 0, 0, 190), 4.0f);
  dl->AddText(ImVec2(x0, y0 - 19.0f), IM_COL32_WHITE, legend.title.c_str());
  const int steps = 32;
  for (int i = 0; i < steps; ++i) {
    vec3 a = heat_srgb(float(i) / steps), b = heat_srgb(float(i + 1) / steps);
    auto col = [](vec3 c) { return IM_COL32(int(c.x * 255), int(c.y * 255), int(c.z * 255), 255); };
    dl->AddRectFilledMultiColor(ImVec2(x0 + w * i / steps, y0), ImVec2(x0 + w * (i + 1) / steps, y0 + h), col(a),
                                col(b), col(b), col(a));
  }
  const int ticks = legend.log ? int(std::lround(std::log10(legend.hi / legend.lo))) : 4;
  for (int k = 0; k <= ticks; ++k) {
    double v = legend.log ? legend.lo * std::pow(10.0, k) : legend.lo + (legend.hi - legend.lo) * k / ticks;
    char label[32];
    std::snprintf(label, sizeof label, legend.log ? "%g" : "%.0f", v);
    float tx = x0 + w * float(k) / float(ticks);
    dl->AddLine(ImVec2(tx, y0 + h), ImVec2(tx, y0 + h + 4), IM_COL32_WHITE);
    dl->AddText(ImVec2(tx - ImGui::CalcTextSize(label).x * 0.5f, y0 + h + 5), IM_COL32_WHITE, label);
  }
}

bool report(const std::optional<Error>& err) {
  if (!err) return false;
  std::fprintf(stderr, "ptview: error: %s\n", err->message.c_str());
  return true;
}

}  // namespace

int run_viewer(const RenderParams& params, const DisplaySettings& display, const ViewerHooks& hooks, Scene scene,
               OffloadRoot* offload) {
  ScriptRun script;
  if (!hooks.script.empty()) {
    Result<std::vector<ScriptCommand>> cmds = load_script(hooks.script);
    if (!cmds) {
      std::fprintf(stderr, "ptview: error: %s\n", cmds.error().c_str());
      return 2;
    }
    script.file = hooks.script;
    script.commands = std::move(*cmds);
  }
  GLFWwindow* window = open_window(params);
  if (!window) return 2;
  InputState input;
  g_input = &input;
  glfwSetScrollCallback(window, [](GLFWwindow*, double, double y) { g_input->scroll += y; });
  glfwSetDropCallback(window, [](GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i) g_input->dropped.emplace_back(paths[i]);
  });
  const float xscale = init_imgui(window);
  GlDisplay gl;
  if (std::string err = gl.init(); !err.empty()) {
    std::fprintf(stderr, "ptview: error: %s\n", err.c_str());
    close_window(window);
    return 2;
  }

  ViewerState st;
  st.adaptive = hooks.adaptive;
  st.offload = offload;
  RenderParams start = params;
  bool lock_size = hooks.lock_size;
  if (!hooks.reference.empty()) {
    Result<Image> ref = load_image(hooks.reference);
    std::string err = ref ? "" : ref.error();
    if (ref && hooks.lock_size && (ref->width != params.width || ref->height != params.height))
      err = hooks.reference + ": reference is " + std::to_string(ref->width) + "x" + std::to_string(ref->height) +
            ", the render " + std::to_string(params.width) + "x" + std::to_string(params.height);
    if (!err.empty()) {
      std::fprintf(stderr, "ptview: error: %s\n", err.c_str());
      gl.destroy();
      close_window(window);
      return 2;
    }
    // The render keeps the reference's size (it no longer follows the window).
    start.width = ref->width;
    start.height = ref->height;
    lock_size = true;
    st.reference = std::move(*ref);
  }
  st.init(std::move(scene), start, display, params.threads);
  PanelState panels;
  panels.save_path = hooks.out.empty() ? "ptview.png" : hooks.out;
  panels.lock_size = lock_size;
  Image shown, shown_b;
  HeatLegend legend;
  bool heat = false, heat_b = false, divider_drag = false;
  GlDisplay gl_b;
  if (std::string err = gl_b.init(); !err.empty()) {
    std::fprintf(stderr, "ptview: error: %s\n", err.c_str());
    gl.destroy();
    close_window(window);
    return 2;
  }
  SizeFollower follow;
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
    // HiDPI: everything in framebuffer pixels.
    int fb_w, fb_h, ww, wh;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    glfwGetWindowSize(window, &ww, &wh);
    const ImageArea area = image_area(fb_w, fb_h, ww, float(kPanelWidth) * xscale, st.params.width, st.params.height);

    st.poll_load();
    st.poll_saves();
    bool divider_mouse = drag_divider(window, st, area, io.WantCaptureMouse, divider_drag);
    if (process_input(window, input, st, area, dt, io.WantCaptureMouse || divider_mouse, io.WantCaptureKeyboard))
      panels.open_material = true;
    const ivec2 follow_to = followed_size(area);
    script.window = {ww, wh, follow_to.x, follow_to.y, !follows_area(area, panels.lock_size)};
    if (!script.done()) script.step(st);
    if (script.window_request) glfwSetWindowSize(window, (*script.window_request)[0], (*script.window_request)[1]);
    const double seconds = std::chrono::duration<double>(now.time_since_epoch()).count();
    if (auto size = follow.update(area, panels.lock_size, ivec2(st.params.width, st.params.height), seconds)) {
      RenderParams p = st.params;
      p.width = size->x;
      p.height = size->y;
      st.apply(RenderParamsEdit{p});
    }
    st.tick_compare();
    const bool dirty = st.display_dirty;
    fetch_frame(st, gl, shown, legend, heat);
    fetch_frame_b(st, gl_b, shown_b, heat_b, dirty);

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    draw_panels(st, panels, float(kPanelWidth) * xscale, float(wh));
    if (st.compare) {
      ImDrawList* dl = ImGui::GetForegroundDrawList();
      const float x = float(divider_window_x(area, st.divider));
      const float top = float(fb_h - area.rect.y - area.rect.h) / area.to_fb,
                  bottom = float(fb_h - area.rect.y) / area.to_fb;
      dl->AddLine(ImVec2(x, top), ImVec2(x, bottom), IM_COL32(255, 255, 255, 220), 2.0f);
      dl->AddText(ImVec2(x - 16, top + 4), IM_COL32_WHITE, "A");
      dl->AddText(ImVec2(x + 8, top + 4), IM_COL32_WHITE, "B");
    }
    if (heat)
      draw_legend(legend, float(area.panel_px) / area.to_fb, float(fb_w) / area.to_fb, float(fb_h) / area.to_fb);
    ImGui::Render();
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    // A heatmap is already display-ready: exposure 0 and the clamp tonemap leave its colours as they are.
    if (st.compare) {
      // A left of the divider, B right: the same rectangle drawn twice, each clipped to its side.
      const int split = int(std::lround(st.divider * area.rect.w));
      glEnable(GL_SCISSOR_TEST);
      glScissor(area.rect.x, area.rect.y, split, area.rect.h);
      gl.draw(area.rect.x, area.rect.y, area.rect.w, area.rect.h, heat ? DisplaySettings{} : st.display);
      glScissor(area.rect.x + split, area.rect.y, area.rect.w - split, area.rect.h);
      gl_b.draw(area.rect.x, area.rect.y, area.rect.w, area.rect.h, heat_b ? DisplaySettings{} : st.display);
      glDisable(GL_SCISSOR_TEST);
    } else {
      gl.draw(area.rect.x, area.rect.y, area.rect.w, area.rect.h, heat ? DisplaySettings{} : st.display);
    }
    glViewport(0, 0, fb_w, fb_h);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ++st.ui_frames;

    if (!script.screenshot_request.empty() && report(save_framebuffer_png(script.screenshot_request, fb_w, fb_h)))
      exit_code = 2;
    bool quit = script.quit;
    if (hooks.quit_after_frames && script.done() && !st.loading.valid() &&
        st.frame.epoch == st.session->epoch() && st.frame.frames >= *hooks.quit_after_frames)
      quit = true;
    if (quit && !hooks.screenshot.empty() && report(save_framebuffer_png(hooks.screenshot, fb_w, fb_h)))
      exit_code = 2;
    glfwSwapBuffers(window);
    if (quit) break;
  }
  st.poll_saves(true);
  for (const Error& e : st.save_errors) {
    report(e);
    exit_code = 2;
  }
  if (!hooks.stats_json.empty() && report(write_file_atomic(hooks.stats_json, st.stats_json()))) exit_code = 2;
  st.session.reset();
  st.session_b.reset();
  gl.destroy();
  gl_b.destroy();
  close_window(window);
  if (exit_code == 0 && script.failures > 0) exit_code = 3;
  return exit_code;
}

}  // namespace pt
