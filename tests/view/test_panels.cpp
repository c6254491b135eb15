// The ImGui panels driven as a user drives them, without a window or GL: a headless ImGui context, the mouse moved
// over the panels to find each widget (the widget under the mouse is ImGui's hovered id, and a widget's id is the
// hash of its label under its parents' ids, as ImGui computes it), clicks, Ctrl+clicks that turn a slider into a
// text field, typed text and Enter. Each test checks that the panel's change reached the viewer state through
// ViewerState::apply (the one edit path: what changed, and whether rendering restarted), and that looking,
// hovering, opening and collapsing never restart rendering.
#include <gtest/gtest.h>

#include <imgui.h>
#include <imgui_internal.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "view/panels.h"
#include "view/viewer_state.h"
#include "fake_offload.h"
#include "temp_dir.h"
#include "viewer_fixtures.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

constexpr float kPanelWidth = 360.0f, kPanelHeight = 1500.0f;
const ImVec2 kAway(-1e4f, -1e4f);  // a mouse position over no widget
// Our own key indices in io.KeysDown (ImGui 1.86 maps its named keys through io.KeyMap).
constexpr int kEnter = 1, kKeyA = 2, kBackspace = 3;

/// A widget's id: the hash of each label (or integer index) of its path, seeded by its parent's id, as ImGui's
/// PushID and GetID compute it.
struct IdPath {
  ImGuiID id;
  IdPath then(const char* label) const { return {ImHashStr(label, 0, id)}; }
  IdPath then(int index) const { return {ImHashData(&index, sizeof index, id)}; }
};

/// One headless ImGui context drawing draw_panels over a viewer state (start() gives it a scene and a session).
class PanelHarness {
 public:
  PanelHarness() {
    ctx_ = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(kPanelWidth + 40.0f, kPanelHeight);
    io.DeltaTime = 1.0f / 60.0f;
    io.KeyMap[ImGuiKey_Enter] = kEnter;
    io.KeyMap[ImGuiKey_A] = kKeyA;
    io.KeyMap[ImGuiKey_Backspace] = kBackspace;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsAlpha8(&pixels, &w, &h);  // builds the font atlas NewFrame needs
    io.MousePos = kAway;
    // The clipboard is the harness's string: ImGui ends a log (text()) at the End() of the window it ran through
    // by handing the text to the clipboard.
    io.ClipboardUserData = this;
    io.SetClipboardTextFn = [](void* self, const char* text) { static_cast<PanelHarness*>(self)->clipboard_ = text; };
    io.GetClipboardTextFn = [](void* self) { return static_cast<PanelHarness*>(self)->clipboard_.c_str(); };
    ps.save_path = dir / "ptview.png";
    ps.scene_path = dir / "scene.json";
  }
  ~PanelHarness() { ImGui::DestroyContext(ctx_); }
  PanelHarness(const PanelHarness&) = delete;
  PanelHarness& operator=(const PanelHarness&) = delete;

  test::TempDir dir;  ///< the panels' file names point here, so no click writes into the working directory
  ViewerState st;
  PanelState ps;
  bool fetch = true;

  /// One UI frame: the latest rendered frame fetched, as the viewer does (unless `fetch` is off: a test that sets
  /// the frame's figures itself), and the panels drawn.
  void frame() { draw(false); }
  /// One UI frame, returning the text the panels show (ImGui's log of the rendered text, a line per row; the
  /// headers stay as they are).
  std::string text() {
    clipboard_.clear();
    draw(true);
    return clipboard_;
  }
  void frames(int n) {
    for (int i = 0; i < n; ++i) frame();
  }
  /// UI frames, a millisecond apart, until `done()` holds (a generous deadline of about 6 s: a hang, not
  /// slowness, fails). Returns whether it holds.
  template <class Done>
  bool frames_until(Done done) {
    for (int i = 0; i < 6000 && !done(); ++i) {
      frame();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return done();
  }

  /// The panels' one window (draw_panels names it "ptview").
  static ImGuiWindow* panel_window() { return ImGui::FindWindowByName("ptview"); }
  static IdPath panel() { return {panel_window()->ID}; }
  /// The open combo's list (ImGui draws it as a popup window).
  static IdPath popup() { return {popup_window()->ID}; }

  /// Where the mouse hovers `target`: the main window's (or the open popup's) area swept row by row. Fails the
  /// test when no point does.
  ImVec2 find(IdPath target) {
    if (auto known = found_.find(target.id); known != found_.end()) {  // where it was, unless the layout moved
      ImGui::GetIO().MousePos = known->second;
      frame();
      if (ImGui::GetCurrentContext()->HoveredId == target.id) return known->second;
    }
    ImGuiWindow* w = ImGui::GetCurrentContext()->OpenPopupStack.empty() ? panel_window() : popup_window();
    const ImVec2 lo = w->Pos, hi = ImVec2(w->Pos.x + w->Size.x, w->Pos.y + w->Size.y);
    for (float y = lo.y + 1.0f; y < hi.y; y += 3.0f)
      for (float x = lo.x + 4.0f; x < hi.x; x += 9.0f) {
        ImGui::GetIO().MousePos = ImVec2(x, y);
        frame();
        if (ImGui::GetCurrentContext()->HoveredId == target.id) return found_[target.id] = ImVec2(x, y);
      }
    ADD_FAILURE() << "no widget with id " << target.id << " under the mouse";
    return kAway;
  }

  /// Press and release the left button over `target` (a button, checkbox, header, combo or list entry).
  void click(IdPath target, bool ctrl = false) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = find(target);
    io.KeyCtrl = ctrl;
    io.MouseDown[0] = true;
    frame();
    io.MouseDown[0] = false;
    frame();
    io.KeyCtrl = false;
    frame();
  }
  /// Ctrl+click a slider or drag (a text field then) or click a text field, replace its text and press Enter.
  void type(IdPath target, std::string_view text, bool ctrl_click = true) {
    click(target, ctrl_click);
    ImGuiIO& io = ImGui::GetIO();
    io.KeyCtrl = true;  // select all
    io.KeysDown[kKeyA] = true;
    frame();
    io.KeyCtrl = false;
    io.KeysDown[kBackspace] = true;
    frame();
    for (char c : text) io.AddInputCharacter(static_cast<unsigned>(c));
    frame();
    io.KeysDown[kEnter] = true;
    frame();
    frames(2);
  }
  /// Press the left button over `target`, move the mouse `dx` to the right, release (a drag).
  void drag(IdPath target, float dx) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = find(target);
    io.MouseDown[0] = true;
    frame();
    io.MousePos.x += dx;
    frame();
    io.MouseDown[0] = false;
    frames(2);
  }
  /// Open the combo `combo` and pick the entry `entry`.
  void choose(IdPath combo, const char* entry) {
    click(combo);
    ASSERT_FALSE(ImGui::GetCurrentContext()->OpenPopupStack.empty()) << "the combo did not open";
    click(popup().then(entry));
    EXPECT_TRUE(ImGui::GetCurrentContext()->OpenPopupStack.empty()) << "the combo stayed open";
  }
  /// Move the mouse away from every widget.
  void leave() {
    ImGui::GetIO().MousePos = kAway;
    frames(2);
  }

 private:
  static ImGuiWindow* popup_window() { return ImGui::GetCurrentContext()->OpenPopupStack.back().Window; }
  void draw(bool log) {
    if (fetch) st.fetch_frame();
    ImGui::NewFrame();
    if (log) ImGui::LogToClipboard(0);  // 0: opens no collapsed header
    draw_panels(st, ps, kPanelWidth, kPanelHeight);
    ImGui::Render();
    for (bool& k : ImGui::GetIO().KeysDown) k = false;
  }
  ImGuiContext* ctx_ = nullptr;
  std::string clipboard_;
  std::map<ImGuiID, ImVec2> found_;
};

using test::builtin;
using test::small_params;

/// A harness over `scene` (the Cornell box by default), its session rendering on one thread.
void start(PanelHarness& h, Scene scene = builtin("cornell")) {
  h.st.init(std::move(scene), small_params(), {}, 1);
  h.frames(2);
}

/// test::floor_under_a_sphere_light, seen from the front.
Scene floor_under_a_sphere_light() {
  Scene s = test::floor_under_a_sphere_light();
  s.camera = Camera{};
  s.camera->eye = vec3(0, 1, 4);
  s.camera->target = vec3(0, 0.5f, 0);
  return s;
}

TEST(Panels, LookingHoveringOpeningAndClosingNeverRestart) {
  PanelHarness h;
  start(h);
  const int restarts = h.st.restarts;
  const RenderParams before = h.st.params;
  // Sweep the mouse over every row of the column (find fails only at the end, for an id no widget has).
  ImGuiWindow* w = PanelHarness::panel_window();
  for (float y = w->Pos.y; y < w->Pos.y + w->Size.y; y += 5.0f)
    for (float x = 2.0f; x < kPanelWidth; x += 25.0f) {
      ImGui::GetIO().MousePos = ImVec2(x, y);
      h.frame();
    }
  h.click(PanelHarness::panel().then("Camera"));   // opens
  h.click(PanelHarness::panel().then("Compare"));  // opens
  h.click(PanelHarness::panel().then("Render"));   // collapses
  h.click(PanelHarness::panel().then("Render"));   // opens again
  h.click(PanelHarness::panel().then("Camera"));   // collapses
  h.leave();
  EXPECT_EQ(h.st.restarts, restarts);
  EXPECT_EQ(h.st.params.max_depth, before.max_depth);
  EXPECT_EQ(h.st.params.integrator, before.integrator);
  EXPECT_FALSE(h.st.compare.has_value());
}

/// Whether the collapsing header `label` of the column, open by default, is open (ImGui keeps the state in the
/// window's storage once it has changed).
bool default_open_header_is_open(const char* label) {
  return PanelHarness::panel_window()->StateStorage.GetInt(PanelHarness::panel().then(label).id, 1) != 0;
}

TEST(Panels, PickingAnObjectBringsTheMaterialPanelForward) {
  PanelHarness h;
  start(h);
  ASSERT_TRUE(default_open_header_is_open("Material"));  // open by default
  h.click(PanelHarness::panel().then("Material"));
  ASSERT_FALSE(default_open_header_is_open("Material"));
  h.ps.open_material = true;  // as a click in the image does
  h.frame();
  EXPECT_TRUE(default_open_header_is_open("Material"));
  EXPECT_FALSE(h.ps.open_material);
  h.click(PanelHarness::panel().then("Material"));  // and the user can close it again
  EXPECT_FALSE(default_open_header_is_open("Material"));
}

TEST(Panels, TheRenderPanelsSettingsRestartWithTheNewParameters) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  int restarts = h.st.restarts;
  h.choose(p.then("integrator"), "bsdf");
  EXPECT_EQ(h.st.params.integrator, IntegratorKind::bsdf);
  EXPECT_EQ(h.st.restarts, ++restarts);
  h.choose(p.then("light sampling"), "area");
  EXPECT_EQ(h.st.params.light_sampling, LightSampling::area);
  h.choose(p.then("sampler"), "independent");
  EXPECT_EQ(h.st.params.sampler, SamplerKind::independent);
  restarts = h.st.restarts;
  h.type(p.then("max depth"), "3");
  EXPECT_EQ(h.st.params.max_depth, 3);
  EXPECT_EQ(h.st.restarts, restarts + 1);
  h.type(p.then("spp / frame"), "5");
  EXPECT_EQ(h.st.params.spp_per_frame, 5);
  h.type(p.then("threads"), "2");
  EXPECT_EQ(h.st.params.threads, 2);
  // The size applies on Enter only, and locks it (the render no longer follows the window).
  ASSERT_FALSE(h.ps.lock_size);
  h.type(p.then("size").then(0), "20", false);
  h.type(p.then("size").then(1), "0", false);  // clamped to 1
  EXPECT_EQ(h.st.params.width, 20);
  EXPECT_EQ(h.st.params.height, 1);
  EXPECT_TRUE(h.ps.lock_size);
  h.click(p.then("lock"));
  EXPECT_FALSE(h.ps.lock_size);
  // The same choice again restarts nothing.
  restarts = h.st.restarts;
  h.choose(p.then("integrator"), "bsdf");
  EXPECT_EQ(h.st.restarts, restarts);
  h.click(p.then("restart"));
  EXPECT_EQ(h.st.restarts, restarts + 1);
}

TEST(Panels, PauseAdaptiveSamplingAndStopAtSppDoNotRestart) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  const int restarts = h.st.restarts;
  h.click(p.then("pause"));
  EXPECT_TRUE(h.st.paused);
  EXPECT_TRUE(h.st.session->paused());
  h.click(p.then("pause"));
  EXPECT_FALSE(h.st.session->paused());
  ASSERT_FALSE(h.st.adaptive.enabled());
  h.click(p.then("adaptive"));
  EXPECT_TRUE(h.st.adaptive.enabled());
  EXPECT_NEAR(h.st.adaptive.noise_threshold, 0.01, 1e-6);  // the slider's value while it was off
  h.type(p.then("threshold"), "0.05");
  EXPECT_NEAR(h.st.adaptive.noise_threshold, 0.05, 1e-6);
  h.click(p.then("adaptive"));
  EXPECT_FALSE(h.st.adaptive.enabled());
  EXPECT_NEAR(h.ps.noise_threshold, 0.05, 1e-6);  // kept for the next time it is turned on
  h.click(p.then("adaptive"));
  EXPECT_NEAR(h.st.adaptive.noise_threshold, 0.05, 1e-6);
  h.type(p.then("stop at spp").then(""), "7", false);
  EXPECT_EQ(h.st.target_spp, 7);
  EXPECT_EQ(h.st.session->target_spp(), 7);
  h.type(p.then("stop at spp").then(""), "-4", false);
  EXPECT_EQ(h.st.target_spp, 0);
  EXPECT_EQ(h.st.session->target_spp(), 0);
  h.st.apply(StopEdit{12});  // as a script's stop-at-spp: the field shows it, and its + counts on from it
  h.click(p.then("stop at spp").then("+"));
  EXPECT_EQ(h.st.target_spp, 13);
  EXPECT_EQ(h.st.session->target_spp(), 13);
  EXPECT_EQ(h.st.restarts, restarts);
}

TEST(Panels, SaveImageWritesTheFileOrSaysWhichExtensionsWork) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  const test::TempDir& dir = h.dir;
  const std::string bad = (dir.path / "image.bmp").string(), good = (dir.path / "image.pfm").string();
  h.type(p.then("file"), bad, false);
  EXPECT_EQ(h.ps.save_path, bad);
  h.click(p.then("save image"));
  EXPECT_EQ(h.st.status, bad + ": use .png, .exr or .pfm");
  EXPECT_FALSE(fs::exists(bad));
  h.type(p.then("file"), good, false);
  h.click(p.then("save image"));
  EXPECT_EQ(h.st.status, "saving " + good);
  h.st.poll_saves(true);
  EXPECT_EQ(h.st.status, "saved " + good) << "the status line says when the file is written";
  EXPECT_TRUE(fs::exists(good));
  // A save that fails says why on the status line, and is kept for the exit code. (A directory where the file
  // should go: the write fails even as root.)
  const std::string blocked = (dir.path / "blocked.png").string();
  fs::create_directory(blocked);
  h.type(p.then("file"), blocked, false);
  h.click(p.then("save image"));
  h.st.poll_saves(true);
  ASSERT_EQ(h.st.save_errors.size(), 1u);
  EXPECT_EQ(h.st.status, h.st.save_errors[0].message);
  EXPECT_NE(h.st.status.find(blocked), std::string::npos) << h.st.status;
}

TEST(Panels, TheCameraPanelMovesTheCameraAndResetsIt) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  h.click(p.then("Camera"));
  const Camera home = h.st.home_camera;
  int restarts = h.st.restarts;
  ASSERT_NE(home.fov_deg, 30.0f);
  h.type(p.then("fov"), "30");
  EXPECT_FLOAT_EQ(h.st.scene.camera->fov_deg, 30.0f);
  EXPECT_EQ(h.st.restarts, ++restarts);
  h.type(p.then("eye").then(1), "0.25");
  EXPECT_FLOAT_EQ(h.st.scene.camera->eye.y, 0.25f);
  EXPECT_FLOAT_EQ(h.st.scene.camera->eye.x, home.eye.x);
  h.type(p.then("target").then(2), "-1.5");
  EXPECT_FLOAT_EQ(h.st.scene.camera->target.z, -1.5f);
  restarts = h.st.restarts;
  h.type(p.then("orbit distance"), "2");
  EXPECT_NEAR(glm::length(h.st.scene.camera->eye - h.st.scene.camera->target), 2.0f, 1e-4f);
  EXPECT_EQ(h.st.restarts, restarts + 1);
  restarts = h.st.restarts;
  h.click(p.then("reset camera (R)"));
  EXPECT_EQ(h.st.scene.camera->eye, home.eye);
  EXPECT_EQ(h.st.scene.camera->target, home.target);
  EXPECT_EQ(h.st.scene.camera->fov_deg, home.fov_deg);
  EXPECT_EQ(h.st.restarts, restarts + 1);
}

TEST(Panels, TheMaterialPanelEditsTheChosenMaterial) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  ASSERT_GE(h.st.scene.materials.size(), 2u);
  const size_t i = 1;
  const std::string name = h.st.scene.materials[i].name;
  ASSERT_FALSE(name.empty());
  h.choose(p.then("material"), (name + "##" + std::to_string(i)).c_str());
  ASSERT_EQ(h.st.selected_material, int(i));
  int restarts = h.st.restarts;
  h.type(p.then("albedo").then("##Y"), "128");  // ColorEdit3's components are 0-255 integers
  EXPECT_NEAR(h.st.scene.materials[i].albedo.y, 128.0f / 255.0f, 1e-6f);
  EXPECT_EQ(h.st.restarts, ++restarts);
  h.type(p.then("albedo").then("##X"), "51");
  EXPECT_NEAR(h.st.scene.materials[i].albedo.x, 0.2f, 1e-6f);
  h.type(p.then("emission").then("##Z"), "3.5");
  EXPECT_FLOAT_EQ(h.st.scene.materials[i].emission.z, 3.5f);
  restarts = h.st.restarts;
  h.choose(p.then("type"), name_of(h.st.scene.materials[i].type));  // the same type again: nothing to restart
  EXPECT_EQ(h.st.restarts, restarts);
  h.choose(p.then("type"), "glass");
  EXPECT_EQ(h.st.scene.materials[i].type, MaterialType::glass);
  EXPECT_EQ(h.st.restarts, restarts + 1);
  h.type(p.then("ior"), "1.8");
  EXPECT_FLOAT_EQ(h.st.scene.materials[i].ior, 1.8f);
  EXPECT_EQ(h.st.scene.materials[i].name, name);
  EXPECT_EQ(h.st.selected_material, int(i));
}

TEST(Panels, TheLightPanelResizesMovesAndDimsTheChosenLight) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  ASSERT_EQ(h.st.lights.size(), 1u);
  const LightPlacement before = light_placement(h.st.scene, h.st.lights[0]);
  int restarts = h.st.restarts;
  h.type(p.then("size W x H").then(0), "0.125");
  LightPlacement now = light_placement(h.st.scene, h.st.lights[0]);
  EXPECT_NEAR(now.size.x, 0.125f, 1e-5f);
  EXPECT_NEAR(now.size.y, before.size.y, 1e-5f);
  EXPECT_NEAR(glm::length(now.center - before.center), 0.0f, 1e-5f);
  EXPECT_EQ(h.st.restarts, ++restarts);
  // The scale is relative (every frame of a drag scales by its own step): it has no value to type, and a typed one
  // would have been applied on every frame it stayed in the field.
  h.type(p.then("scale"), "1.5");
  now = light_placement(h.st.scene, h.st.lights[0]);
  EXPECT_NEAR(now.size.x, 0.125f, 1e-5f);
  h.drag(p.then("scale"), 20.0f);  // 20 px at 0.005 a pixel
  now = light_placement(h.st.scene, h.st.lights[0]);
  EXPECT_NEAR(now.size.x, 0.1375f, 1e-5f);
  EXPECT_NEAR(now.size.y, 1.1f * before.size.y, 1e-5f);
  h.type(p.then("position").then(0), "0.25");
  now = light_placement(h.st.scene, h.st.lights[0]);
  EXPECT_NEAR(now.center.x, 0.25f, 1e-5f);
  EXPECT_NEAR(now.center.y, before.center.y, 1e-5f);
  const Material& m = h.st.scene.materials[h.st.lights[0].material];
  const vec3 emission = m.emission;
  h.type(p.then("intensity"), "3");
  EXPECT_NEAR(max_component(m.emission), 3.0f, 1e-5f);
  EXPECT_NEAR(m.emission.y / m.emission.x, emission.y / emission.x, 1e-5f);  // the colour kept
  h.type(p.then("color").then("##Z"), "0");
  EXPECT_EQ(m.emission.z, 0.0f);
  EXPECT_NEAR(max_component(m.emission), 3.0f, 1e-5f);
}

TEST(Panels, TheLightPanelResizesASphereByItsRadius) {
  PanelHarness h;
  start(h, floor_under_a_sphere_light());
  const IdPath p = PanelHarness::panel();
  ASSERT_EQ(h.st.lights.size(), 1u);
  ASSERT_EQ(h.st.lights[0].kind, SceneLightKind::sphere);
  const int restarts = h.st.restarts;
  h.type(p.then("radius"), "0.0625");
  EXPECT_FLOAT_EQ(h.st.scene.spheres[0].radius, 0.0625f);
  EXPECT_EQ(h.st.scene.spheres[0].center, vec3(0.5f, 1.5f, -0.25f));
  EXPECT_EQ(h.st.restarts, restarts + 1);
}

TEST(Panels, TheDisplayPanelChangesTheViewWithoutARestart) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  const int restarts = h.st.restarts;
  h.type(p.then("exposure"), "1.5");
  EXPECT_FLOAT_EQ(h.st.display.exposure, 1.5f);
  h.choose(p.then("tonemap"), "aces");
  EXPECT_EQ(h.st.display.tonemap, Tonemap::aces);
  h.choose(p.then("show"), "samples");
  EXPECT_EQ(h.st.display_mode, DisplayMode::samples);
  h.choose(p.then("show"), "reference-error");  // no --reference: refused, and said so
  EXPECT_EQ(h.st.display_mode, DisplayMode::samples);
  EXPECT_EQ(h.st.status, "reference-error needs --reference");
  EXPECT_EQ(h.st.restarts, restarts);
}

TEST(Panels, TheComparePanelStartsAndEndsACompare) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  h.click(p.then("Compare"));
  h.click(p.then("compare A | B"));
  ASSERT_TRUE(h.st.compare.has_value());
  EXPECT_EQ(h.st.compare->integrator, h.st.params.integrator);  // B starts as A
  h.choose(p.then("B sampler"), "independent");
  EXPECT_EQ(h.st.compare->sampler, SamplerKind::independent);
  h.choose(p.then("B integrator"), "nee");
  EXPECT_EQ(h.st.compare->integrator, IntegratorKind::nee);
  h.choose(p.then("B light sampling"), "area");
  EXPECT_EQ(h.st.compare->light_sampling, LightSampling::area);
  h.click(p.then("B adaptive"));
  EXPECT_NEAR(h.st.compare->adaptive.noise_threshold, 0.01, 1e-6);
  h.type(p.then("##Bthreshold"), "0.2");
  EXPECT_NEAR(h.st.compare->adaptive.noise_threshold, 0.2, 1e-6);
  h.click(p.then("B adaptive"));
  EXPECT_FALSE(h.st.compare->adaptive.enabled());
  const int restarts = h.st.restarts;
  h.type(p.then("divider"), "0.25");
  EXPECT_FLOAT_EQ(h.st.divider, 0.25f);
  EXPECT_EQ(h.st.restarts, restarts);
  h.type(p.then("stop at spp").then(""), "9", false);  // both sides stop there
  EXPECT_EQ(h.st.session->target_spp(), 9);
  EXPECT_EQ(h.st.session_b->target_spp(), 9);
  h.click(p.then("compare A | B"));
  EXPECT_FALSE(h.st.compare.has_value());
  EXPECT_EQ(h.st.params.sampler, SamplerKind::sobol);  // A kept its own settings
}

TEST(Panels, TheScenePanelSavesAndOpensScenes) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  const test::TempDir& dir = h.dir;
  h.click(p.then("Scene"));
  const std::string saved = (dir.path / "saved.json").string();
  h.type(p.then("scene file"), saved, false);
  h.click(p.then("save scene"));
  ASSERT_TRUE(fs::exists(saved));
  EXPECT_EQ(h.st.status, "saved " + saved);
  const std::string other = (dir.path / "other.json").string();
  fs::copy_file(saved, other);
  h.type(p.then("path"), other, false);
  h.click(p.then("open OBJ / JSON / glTF"));
  ASSERT_TRUE(h.st.loading.valid());
  h.st.loading.wait();
  EXPECT_TRUE(h.st.poll_load());
  EXPECT_EQ(h.st.scene.source, other);
}

/// Whether `text` holds `line` as one of its lines, or as the start of one.
bool shows(const std::string& text, const std::string& line) {
  return ("\n" + text).find("\n" + line) != std::string::npos;
}

/// Whether `text` shows each of `lines`; on failure, the lines it lacks and the text, once.
::testing::AssertionResult shows_all(const std::string& text, std::initializer_list<std::string> lines) {
  std::string missing;
  for (const std::string& line : lines)
    if (!shows(text, line)) missing += "  " + line + "\n";
  if (missing.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "not shown:\n" << missing << "in:\n" << text;
}

// The status line heads the panel column, seen whichever panels are open: with the Scene panel closed (as it
// starts), a refused save and a display mode refused without a reference still say why. The messages before the
// last are kept below it, newest first.
TEST(Panels, TheStatusLineIsSeenWithThePanelsClosed) {
  PanelHarness h;
  start(h);
  const IdPath p = PanelHarness::panel();
  const std::string bad = (h.dir.path / "image.bmp").string();
  h.type(p.then("file"), bad, false);
  h.click(p.then("save image"));
  std::string t = h.text();
  EXPECT_TRUE(shows(t, bad + ": use .png, .exr or .pfm")) << t;
  EXPECT_EQ(t.find("save scene"), std::string::npos) << "the Scene panel is closed";
  h.choose(p.then("show"), "reference-error");
  t = h.text();
  EXPECT_TRUE(shows(t, "reference-error needs --reference")) << t;
  // The message before it is kept under the status line, closed until asked for.
  EXPECT_TRUE(shows(t, "> earlier messages (1)")) << t;
  EXPECT_EQ(t.find(bad + ": use"), std::string::npos) << t;
  h.click(p.then("earlier"));
  t = h.text();
  EXPECT_TRUE(shows_all(
      t, {"reference-error needs --reference", "> earlier messages (1)", "    " + bad + ": use .png, .exr or .pfm"}));
  EXPECT_LT(t.find("earlier messages"), t.find(bad)) << t;
  // Newest first, and at most kEarlierMessages of them: the oldest go.
  for (int i = 0; i < 10; ++i) h.st.say("message " + std::to_string(i));
  t = h.text();
  EXPECT_TRUE(shows_all(t, {"message 9", "> earlier messages (8)", "    message 8", "    message 1"}));
  EXPECT_EQ(t.find("message 0"), std::string::npos) << t;
  EXPECT_EQ(t.find("reference-error needs"), std::string::npos) << t;
  EXPECT_LT(t.find("message 9"), t.find("message 8")) << t;
  EXPECT_LT(t.find("message 8"), t.find("message 1")) << t;
}

/// The Stats panel's figures, from a frame whose values the test sets (the session paused, the harness no longer
/// fetching): each figure worked out by hand, not by the panel's formula.
TEST(Panels, TheStatsPanelShowsTheFramesFigures) {
  PanelHarness h;
  start(h);
  h.click(PanelHarness::panel().then("pause"));
  h.fetch = false;
  SessionFrame& f = h.st.frame;
  f.preview = false;
  f.width = 32;
  f.height = 24;
  f.spp = 40;
  f.seconds = 2.0;
  f.threads = 3;
  f.counters = {};
  f.counters.camera_rays = 3'000'000;
  f.counters.bounce_rays = 2'000'000;
  f.counters.shadow_rays = 1'000'000;
  f.counters.nonfinite_samples = 7;
  f.est_rel_mse = 0.02;
  f.converged = false;
  f.auto_first_spread = kAutoMinSpread;
  f.auto_pilot_gain = 0.25f;
  std::string t = h.text();
  EXPECT_TRUE(shows(t, "32 x 24")) << t;
  EXPECT_FALSE(shows(t, "32 x 24  (preview)")) << t;
  EXPECT_TRUE(shows_all(t, {"spp 40   20.0 spp/s   3.00 Mrays/s",  // 40 / 2 s; 6e6 rays / 2 s
                            "elapsed 2.0 s   threads 3", "est relMSE 0.02", "non-finite samples 7",
                            "auto light sampling: first vertex by solid angle (pilot gain 0.25)"}));
  EXPECT_FALSE(shows(t, "ETA")) << t;          // adaptive sampling is off
  EXPECT_FALSE(shows(t, "true relMSE")) << t;  // no reference
  // The estimate against time, on log scales, over the times of the epoch's first and last frames.
  h.st.error_history = {{0.5, 0.1}, {2.0, 0.02}};
  h.st.reference = Image(32, 24);
  h.st.frame_rel_mse = 0.03;
  t = h.text();
  EXPECT_TRUE(shows_all(t, {"log10 relMSE vs log10 t (0.5..2 s)", "est relMSE 0.02   true relMSE 0.03"}));
  h.st.reference.reset();
  h.st.frame_rel_mse = std::nan("");
  f.auto_first_spread = kAutoMinSpreadDeep;
  f.preview = true;  // a preview's estimate is not shown
  t = h.text();
  EXPECT_TRUE(shows_all(t, {"auto light sampling: first vertex by area (pilot gain 0.25)", "32 x 24  (preview)",
                            "est relMSE: needs 2+ spp"}));
  f.preview = false;

  // Adaptive sampling at T = 0.1: relMSE falls as 1/t from 0.02 at 2 s to T^2 = 0.01 at 4 s, 2 s from now.
  h.st.apply(AdaptiveEdit{{0.1, 0}});
  t = h.text();
  EXPECT_TRUE(shows(t, "ETA to threshold 0.1: 2.0 s")) << t;
  f.est_rel_mse = 0.005;  // already below T^2, some pixels still sampling
  t = h.text();
  EXPECT_TRUE(shows(t, "ETA to threshold: finishing the last pixels")) << t;
  f.converged = true;
  t = h.text();
  EXPECT_TRUE(shows(t, "converged to threshold 0.1")) << t;

  // Restart latency: the median and the 95th percentile of the recorded restarts.
  h.st.restart_latency_ms.clear();
  for (int i = 1; i <= 21; ++i) h.st.restart_latency_ms.push_back(double(i));
  t = h.text();
  EXPECT_TRUE(shows(t, "restart latency p50 11.0 ms  p95 20.0 ms")) << t;
}

/// Under mpirun the Stats panel lists every rank's samples and rate in the shown epoch, and its spp line counts
/// all ranks' samples (view/offload.h): here rank 0's session at its stop and two workers' results delivered by a
/// fake channel, fetched as the viewer's loop fetches (ViewerState::fetch_frame).
TEST(Panels, TheStatsPanelListsEveryRanksSamples) {
  test::Wire wire;
  OffloadRoot root(std::make_unique<test::FakeChannel>(&wire));  // outlives the harness, which points at it
  root.set_ranks(3);
  PanelHarness h;
  h.st.offload = &root;
  start(h);
  ASSERT_EQ(wire.posted.size(), 1u);  // the first epoch, posted to the workers
  h.st.apply(StopEdit{2});
  h.st.apply(RestartEdit{});  // an epoch that stops at 2 spp, whatever the first one had reached
  ASSERT_EQ(wire.posted.size(), 2u);
  const uint64_t epoch = h.st.session->epoch();
  ASSERT_TRUE(h.frames_until([&] { return h.st.frame.epoch == epoch && h.st.frame.spp == 2 && !h.st.frame.preview; }))
      << "epoch " << h.st.frame.epoch << " of " << epoch << ", spp " << h.st.frame.spp;
  const SessionFrame& f = h.st.frame;
  wire.results.push_back(encode_offload_result(epoch, 1, 5, 0.5, test::worker_film(vec3(1.0f), 5, f.width, f.height)));
  wire.results.push_back(encode_offload_result(epoch, 2, 3, 1.5, test::worker_film(vec3(1.0f), 3, f.width, f.height)));
  h.frames(2);
  const std::string t = h.text();
  EXPECT_TRUE(shows_all(t, {"spp 10 ", "rank 0: spp 2 ", "rank 1: spp 5   10.0 spp/s", "rank 2: spp 3   2.0 spp/s"}));
  EXPECT_FALSE(shows(t, "rank 3")) << t;
  // A restart: once its first frame is shown, the workers' results belong to an old epoch, so they show no samples
  // until new ones come.
  h.st.apply(RestartEdit{});
  EXPECT_EQ(wire.posted.size(), 3u);
  ASSERT_TRUE(h.frames_until([&] { return h.st.frame.epoch != epoch; }));
  EXPECT_TRUE(shows_all(h.text(), {"rank 1: spp 0   0.0 spp/s", "rank 2: spp 0   0.0 spp/s"}));
  // The pause checkbox holds the workers too, and releases them (view/offload.h); no restart is posted.
  for (bool held : {true, false}) {
    h.click(PanelHarness::panel().then("pause"));
    h.frames(1);
    ASSERT_EQ(wire.posted.size(), held ? 4u : 5u);
    bool posted = !held;
    ASSERT_TRUE(decode_offload_hold(wire.posted.back(), posted));
    EXPECT_EQ(posted, held);
  }
}

/// What the Render, Light, Camera and Scene panels show of the state: the figures read from their text.
TEST(Panels, ThePanelsShowTheSceneAndTheChosenLight) {
  PanelHarness h;
  RenderParams params = small_params();
  params.threads = 0;  // all cores: the field shows how many that is
  h.st.init(builtin("cornell"), params, {}, 1);
  h.frames(2);
  const IdPath p = PanelHarness::panel();
  h.click(p.then("Scene"));
  h.click(p.then("Camera"));
  std::string t = h.text();
  EXPECT_TRUE(shows(t, "{ " + std::to_string(h.st.session->thread_count()) + " } threads")) << t;
  // The Cornell box's ceiling light, 0.47 x 0.38 at y = 1.98, emitting (17, 12, 4): intensity 17, colour
  // (1, 12/17, 4/17) = (255, 180, 60) in bytes.
  EXPECT_TRUE(shows_all(
      t, {"{ 0: light (rectangle 0.47 x 0.38) } light", "{ 0.47 } { 0.38 } size W x H", "{ 0 } { 1.98 } { 0 } position",
          "{ R:255 } { G:180 } { B: 60 } color", "{ 17.000 } intensity", "material light",
          "{ 3.9 } orbit distance",  // eye (0, 1, 3.9), target (0, 1, 0)
          "triangles 32  spheres 0  lights 1"}));
  EXPECT_FALSE(shows(t, "stopped")) << t;  // adaptive sampling is off
  h.st.scene.warnings = {"a.obj: 2 zero-area triangles dropped"};
  h.st.apply(LightEmissionEdit{0, vec3(1.0f, 0.5f, 0.25f), 8.0f});
  h.st.apply(LightShapeEdit{0, {}, {}, 2.0f});
  h.st.set_paused(true);
  h.fetch = false;
  h.st.apply(AdaptiveEdit{{0.05, 0}});
  h.st.frame.converged_fraction = 0.25;
  h.st.frame.converged = false;
  t = h.text();
  EXPECT_TRUE(shows_all(
      t, {"{ R:255 } { G:128 } { B: 64 } color", "{ 8.000 } intensity", "{ 0.94 } { 0.76 } size W x H",
          "a.obj: 2 zero-area triangles dropped", "[x] adaptive { 0.0500 } threshold", "stopped 25.0% of pixels"}));
  h.st.frame.converged_fraction = 1.0;
  h.st.frame.converged = true;
  t = h.text();
  EXPECT_TRUE(shows(t, "stopped 100.0% of pixels  (converged)")) << t;
}

TEST(Panels, TheStatsPanelComparesBothSidesInEqualTime) {
  PanelHarness h;
  start(h);
  h.st.apply(
      CompareEdit{CompareConfig{h.st.params.integrator, h.st.params.light_sampling, SamplerKind::independent, {}}});
  ASSERT_TRUE(h.st.compare.has_value());
  h.st.set_paused(true);
  h.fetch = false;
  SessionFrame& a = h.st.frame;
  SessionFrame& b = h.st.frame_b;
  a.preview = b.preview = false;
  a.spp = 12;
  a.seconds = 2.0;
  a.est_rel_mse = 0.02;
  b.spp = 30;
  b.seconds = 1.0;
  b.est_rel_mse = 0.01;
  h.st.reference = Image(32, 24);
  h.st.frame_rel_mse = 0.03;
  h.st.frame_b_rel_mse = 0.015;
  std::string t = h.text();
  EXPECT_TRUE(shows(t, "| true relMSE | 0.03 | 0.015 |")) << t;
  // Efficiency 1 / (relMSE x t): A 1 / 0.04, B 1 / 0.01, so B/A = 4.
  EXPECT_TRUE(shows_all(
      t, {"efficiency B/A 4.00", "| spp | 12 | 30 |", "| seconds | 2.00 | 1.00 |", "| est relMSE | 0.02 | 0.01 |"}));
  b.preview = true;  // no estimate on one side: no ratio
  t = h.text();
  EXPECT_TRUE(shows(t, "| est relMSE | 0.02 | - |")) << t;
  EXPECT_FALSE(shows(t, "efficiency")) << t;
}

}  // namespace
}  // namespace pt
