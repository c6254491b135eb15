#include "view/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "render/names.h"
#include "view/camera_control.h"

namespace pt {

namespace {

bool input_text(const char* label, std::string& s) {
  char buf[1024];
  std::snprintf(buf, sizeof buf, "%s", s.c_str());
  bool changed = ImGui::InputText(label, buf, sizeof buf);
  if (changed) s = buf;
  return changed;
}

bool drag_vec3(const char* label, vec3& v, float speed) { return ImGui::DragFloat3(label, &v.x, speed, 0, 0, "%.5g"); }

/// A combo over a name table: lists the table's entries in its order, whatever the enum values are.
template <class E>
bool name_combo(const char* label, std::span<const EnumName<E>> table, E& value) {
  bool changed = false;
  if (ImGui::BeginCombo(label, name_of(table, value))) {
    for (const EnumName<E>& e : table)
      if (ImGui::Selectable(e.name, e.value == value) && e.value != value) {
        value = e.value;
        changed = true;
      }
    ImGui::EndCombo();
  }
  return changed;
}

void render_panel(ViewerState& st, PanelState& ps) {
  RenderParams p = st.params;
  name_combo<IntegratorKind>("integrator", kIntegratorNames, p.integrator);
  name_combo<LightSampling>("light sampling", kLightSamplingNames, p.light_sampling);
  name_combo<SamplerKind>("sampler", kSamplerNames, p.sampler);
  ImGui::SliderInt("max depth", &p.max_depth, 0, 256);
  ImGui::SliderInt("spp / frame", &p.spp_per_frame, 1, 64);
  int threads = p.threads > 0 ? p.threads : st.session->thread_count();
  if (ImGui::SliderInt("threads", &threads, 1, 64)) p.threads = threads;
  int size[2] = {p.width, p.height};
  if (ImGui::InputInt2("size", size, ImGuiInputTextFlags_EnterReturnsTrue)) {
    p.width = std::clamp(size[0], 1, 16384);
    p.height = std::clamp(size[1], 1, 16384);
    ps.lock_size = true;
  }
  ImGui::SameLine();
  ImGui::Checkbox("lock", &ps.lock_size);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("unlocked: the render follows the window");
  st.apply(RenderParamsEdit{p});  // none when nothing changed
  bool paused = st.paused;
  if (ImGui::Checkbox("pause", &paused)) st.set_paused(paused);
  ImGui::SameLine();
  if (ImGui::Button("restart")) st.apply(RestartEdit{});
  AdaptiveParams a = st.adaptive;
  bool adaptive_on = a.enabled();
  float threshold = float(a.enabled() ? a.noise_threshold : ps.noise_threshold);
  bool changed = ImGui::Checkbox("adaptive", &adaptive_on);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("pixels whose relative standard error is below the threshold stop");
  ImGui::SameLine();
  ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.6f);
  changed |= ImGui::SliderFloat("threshold", &threshold, 0.001f, 1.0f, "%.4f", ImGuiSliderFlags_Logarithmic);
  ImGui::PopItemWidth();
  if (changed) {
    ps.noise_threshold = std::clamp(double(threshold), 1e-4, 1.0);
    a.noise_threshold = adaptive_on ? ps.noise_threshold : 0.0;
    st.apply(AdaptiveEdit{a});  // Tier::sampling: no restart
  }
  if (a.enabled())
    ImGui::TextDisabled("stopped %.1f%% of pixels%s", 100.0 * st.frame.converged_fraction,
                        st.frame.converged ? "  (converged)" : "");
  int target = st.target_spp;  // the state's: a script's stop-at-spp shows here too
  if (ImGui::InputInt("stop at spp", &target)) st.apply(StopEdit{std::max(0, target)});
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("0: never stop");
  input_text("file", ps.save_path);
  if (ImGui::Button("save image")) {
    if (is_supported_image_extension(ps.save_path)) st.save_current(ps.save_path);
    else st.say(ps.save_path + ": use .png, .exr or .pfm");
  }
  ImGui::SameLine();
  ImGui::TextDisabled(".png .exr .pfm");
}

void camera_panel(ViewerState& st) {
  Camera c = st.scene.camera.value_or(Camera{});
  const float unit = scene_unit(st.geo.get());
  bool changed = drag_vec3("eye", c.eye, 0.005f * unit);
  changed |= drag_vec3("target", c.target, 0.005f * unit);
  changed |= ImGui::SliderFloat("fov", &c.fov_deg, 5.0f, 120.0f, "%.1f deg");
  const float dist = camera_distance(c);
  float new_dist = dist;
  if (ImGui::DragFloat("orbit distance", &new_dist, 0.005f * unit, camera_min_distance(unit), 1e6f * unit, "%.5g") &&
      dist > 0.0f) {
    dolly_camera(c, new_dist / dist, camera_min_distance(unit));  // the wheel's and the script's motion, and floor
    changed = true;
  }
  if (ImGui::Button("reset camera (R)")) {
    c = st.home_camera;
    changed = true;
  }
  if (changed) st.apply(CameraEdit{c});
}

void material_panel(ViewerState& st) {
  if (st.scene.materials.empty()) return;
  std::string current =
      st.selected_material >= 0 ? st.scene.materials[size_t(st.selected_material)].name : "(click the image)";
  if (ImGui::BeginCombo("material", current.c_str())) {
    for (size_t i = 0; i < st.scene.materials.size(); ++i) {
      std::string label = st.scene.materials[i].name.empty() ? "#" + std::to_string(i) : st.scene.materials[i].name;
      if (ImGui::Selectable((label + "##" + std::to_string(i)).c_str(), int(i) == st.selected_material))
        st.selected_material = int(i);
    }
    ImGui::EndCombo();
  }
  if (st.selected_material < 0) return;
  Material m = st.scene.materials[size_t(st.selected_material)];
  bool changed = name_combo<MaterialType>("type", kMaterialTypeNames, m.type);
  if (info_of(m.type).uses_albedo) changed |= ImGui::ColorEdit3("albedo", &m.albedo.x);
  if (info_of(m.type).uses_ior) changed |= ImGui::SliderFloat("ior", &m.ior, 1.0f, 3.0f);
  changed |= ImGui::ColorEdit3("emission", &m.emission.x, ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_Float);
  if (changed) st.apply(MaterialEdit{st.selected_material, m});
}

void light_panel(ViewerState& st) {
  if (st.lights.empty()) {
    ImGui::TextDisabled("no light in this scene");
    return;
  }
  if (st.selected_light < 0 || st.selected_light >= int(st.lights.size())) st.selected_light = 0;
  const int l = st.selected_light;
  std::string current = std::to_string(l) + ": " + light_label(st.scene, st.lights[size_t(l)]);
  if (ImGui::BeginCombo("light", current.c_str())) {
    for (size_t i = 0; i < st.lights.size(); ++i) {
      std::string label = std::to_string(i) + ": " + light_label(st.scene, st.lights[i]);
      if (ImGui::Selectable(label.c_str(), int(i) == l)) st.selected_light = int(i);
    }
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("or click a light in the image");
  const SceneLight& light = st.lights[size_t(st.selected_light)];
  LightPlacement pl = light_placement(st.scene, light);
  const float unit = scene_unit(st.geo.get()), smallest = 1e-6f * unit;
  if (light.kind == SceneLightKind::sphere) {
    float radius = 0.5f * pl.size.x;
    if (ImGui::DragFloat("radius", &radius, 0.0025f * unit, smallest, 1e3f * unit, "%.4g") && radius > 0.0f &&
        pl.size.x > 0.0f)
      st.apply(LightShapeEdit{st.selected_light, {}, {}, 2.0f * radius / pl.size.x});
  } else {
    float size[2] = {pl.size.x, pl.size.y};
    if (ImGui::DragFloat2("size W x H", size, 0.0025f * unit, smallest, 1e3f * unit, "%.4g")) {
      const vec2 wh(std::max(size[0], smallest), std::max(size[1], smallest));
      st.apply(LightShapeEdit{st.selected_light, {}, wh, {}});
    }
  }
  // Relative: each frame of a drag scales by that frame's step. No text entry (ImGuiSliderFlags_NoInput): a typed
  // factor would be applied again on every frame the field stayed active. A factor of 1 is no edit (apply).
  float scale = 1.0f;
  if (ImGui::DragFloat("scale", &scale, 0.005f, 0.5f, 2.0f, "x %.3f", ImGuiSliderFlags_NoInput))
    st.apply(LightShapeEdit{st.selected_light, {}, {}, scale});
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("drag to scale the light about its centre");
  vec3 center = pl.center;
  if (drag_vec3("position", center, 0.005f * unit)) st.apply(LightShapeEdit{st.selected_light, center, {}, {}});
  const Material& m = st.scene.materials[light.material];
  float intensity = max_component(m.emission);
  vec3 color = intensity > 0.0f ? m.emission / intensity : vec3(1.0f);
  bool changed = ImGui::ColorEdit3("color", &color.x);
  changed |= ImGui::DragFloat("intensity", &intensity, 0.1f, 0.0f, 1e6f);
  if (changed) st.apply(LightEmissionEdit{st.selected_light, color, intensity});
  ImGui::TextDisabled("material %s", m.name.c_str());
}

void scene_panel(ViewerState& st, PanelState& ps) {
  ImGui::TextWrapped("%s", st.scene.source.c_str());
  input_text("path", ps.open_path);
  if (ImGui::Button("open OBJ / JSON / glTF") && !ps.open_path.empty()) st.start_load(ps.open_path);
  ImGui::SameLine();
  ImGui::TextDisabled("(or drop a file)");
  input_text("scene file", ps.scene_path);
  if (ImGui::Button("save scene")) st.save_scene(ps.scene_path);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("a version-1 JSON of what the window shows: camera, materials, lights, meshes");
  if (st.loading.valid() && st.load_progress) {
    const LoadProgress& lp = *st.load_progress;
    double s = std::chrono::duration<double>(Clock::now() - lp.started).count();
    if (lp.stage == 0)
      ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "loading %s: parsing ... %.1f s", st.loading_path.c_str(), s);
    else
      ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "loading %s: building the BVH of %zu triangles ... %.1f s",
                         st.loading_path.c_str(), lp.triangles.load(), s);
    ImGui::TextDisabled("the current scene stays live meanwhile");
  }
  if (st.render_scene) {
    const TraceGeometry& t = st.render_scene->trace();
    ImGui::Text("triangles %u  spheres %zu  lights %zu", st.render_scene->triangle_count(),
                st.render_scene->geo->spheres.size(), st.lights.size());
    ImGui::Text("BVH8 nodes %zu  blocks %zu  build %.1f ms", t.triangles.node_count, t.triangles.block_count,
                t.stats.build_ms);
  }
  for (const std::string& w : st.scene.warnings) ImGui::TextColored(ImVec4(1, 0.7f, 0.3f, 1), "%s", w.c_str());
}

void display_panel(ViewerState& st) {
  DisplayMode mode = st.display_mode;
  if (name_combo<DisplayMode>("show", kDisplayModeNames, mode) && st.apply(DisplayModeEdit{mode}) == Tier::none)
    st.say("reference-error needs --reference");
  DisplaySettings d = st.display;
  bool changed = ImGui::SliderFloat("exposure", &d.exposure, -8.0f, 8.0f, "%.2f stops");
  changed |= name_combo<Tonemap>("tonemap", kTonemapNames, d.tonemap);
  if (changed) st.apply(DisplayEdit{d});
}

/// Estimated (and, with --reference, true) relMSE, the error-vs-time plot and the ETA to the noise threshold.
void convergence_stats(const ViewerState& st) {
  const SessionFrame& f = st.frame;
  if (f.preview || !std::isfinite(f.est_rel_mse) || f.est_rel_mse <= 0) {
    ImGui::TextDisabled("est relMSE: needs 2+ spp");
  } else {
    ImGui::Text("est relMSE %.3g", f.est_rel_mse);
  }
  double rel = st.true_rel_mse();
  if (std::isfinite(rel)) {
    ImGui::SameLine();
    ImGui::Text("  true relMSE %.3g", rel);
  }
  const auto& hist = st.error_history;
  if (hist.size() >= 2) {
    // log-log: resampled at even steps of log10(time) so early frames are not squeezed into the left edge.
    constexpr int kPoints = 64;
    float values[kPoints];
    double t0 = std::log10(hist.front().first), t1 = std::log10(hist.back().first);
    size_t j = 0;
    for (int i = 0; i < kPoints; ++i) {
      double t = t0 + (t1 - t0) * i / (kPoints - 1);
      while (j + 1 < hist.size() && std::log10(hist[j + 1].first) <= t) ++j;
      values[i] = float(std::log10(hist[j].second));
    }
    char overlay[64];
    std::snprintf(overlay, sizeof overlay, "log10 relMSE vs log10 t (%.2g..%.2g s)", hist.front().first,
                  hist.back().first);
    ImGui::PlotLines("##error", values, kPoints, 0, overlay, FLT_MAX, FLT_MAX,
                     ImVec2(ImGui::GetContentRegionAvail().x, 70));
  }
  if (st.adaptive.enabled() && std::isfinite(f.est_rel_mse) && f.est_rel_mse > 0 && f.seconds > 0) {
    // relMSE falls as 1/t, and the threshold bounds each pixel's relative standard error, so the image is done
    // about when its relMSE reaches threshold^2: t_done = t * est / T^2.
    double target = st.adaptive.noise_threshold * st.adaptive.noise_threshold;
    double eta = f.seconds * f.est_rel_mse / target - f.seconds;
    if (f.converged) ImGui::Text("converged to threshold %.3g", st.adaptive.noise_threshold);
    else if (eta <= 0) ImGui::Text("ETA to threshold: finishing the last pixels");
    else ImGui::Text("ETA to threshold %.3g: %.1f s", st.adaptive.noise_threshold, eta);
  }
}

/// Equal-time A/B compare: B's settings (a CompareEdit: both restart) and each side's figures.
void compare_panel(ViewerState& st) {
  bool on = st.compare.has_value();
  CompareConfig c =
      st.compare.value_or(CompareConfig{st.params.integrator, st.params.light_sampling, st.params.sampler, {}});
  bool changed = ImGui::Checkbox("compare A | B", &on);
  if (on) {
    changed |= name_combo<IntegratorKind>("B integrator", kIntegratorNames, c.integrator);
    changed |= name_combo<LightSampling>("B light sampling", kLightSamplingNames, c.light_sampling);
    changed |= name_combo<SamplerKind>("B sampler", kSamplerNames, c.sampler);
    bool adaptive = c.adaptive.enabled();
    float t = float(adaptive ? c.adaptive.noise_threshold : 0.01);
    changed |= ImGui::Checkbox("B adaptive", &adaptive);
    ImGui::SameLine();
    changed |= ImGui::SliderFloat("##Bthreshold", &t, 0.001f, 1.0f, "%.4f", ImGuiSliderFlags_Logarithmic);
    c.adaptive.noise_threshold = adaptive ? double(t) : 0.0;
    float d = st.divider;
    if (ImGui::SliderFloat("divider", &d, 0.0f, 1.0f)) st.apply(DividerEdit{d});
  }
  if (changed) st.apply(CompareEdit{on ? std::optional<CompareConfig>(c) : std::nullopt});
}

void compare_stats(const ViewerState& st) {
  if (!st.compare) return;
  const SessionFrame* f[2] = {&st.frame, &st.frame_b};
  const double rel[2] = {st.true_rel_mse(), st.frame_b_rel_mse};
  double work[2] = {0, 0};  // relMSE x seconds: lower is more efficient
  if (ImGui::BeginTable("ab", 3, ImGuiTableFlags_Borders)) {
    ImGui::TableSetupColumn("");
    ImGui::TableSetupColumn("A");
    ImGui::TableSetupColumn("B");
    ImGui::TableHeadersRow();
    auto row = [&](const char* name, auto&& cell) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(name);
      for (int k = 0; k < 2; ++k) {
        ImGui::TableNextColumn();
        cell(k);
      }
    };
    row("spp", [&](int k) { ImGui::Text("%d", f[k]->spp); });
    row("seconds", [&](int k) { ImGui::Text("%.2f", f[k]->seconds); });
    row("est relMSE", [&](int k) {
      bool ok = !f[k]->preview && std::isfinite(f[k]->est_rel_mse) && f[k]->est_rel_mse > 0;
      if (ok) work[k] = f[k]->est_rel_mse * f[k]->seconds;
      ok ? ImGui::Text("%.3g", f[k]->est_rel_mse) : ImGui::TextDisabled("-");
    });
    if (st.reference)
      row("true relMSE",
          [&](int k) { std::isfinite(rel[k]) ? ImGui::Text("%.3g", rel[k]) : ImGui::TextDisabled("-"); });
    ImGui::EndTable();
  }
  // Efficiency = 1 / (relMSE x time) (Veach's figure of merit); B/A > 1: B converges faster in equal time.
  if (work[0] > 0 && work[1] > 0) ImGui::Text("efficiency B/A %.2f", work[0] / work[1]);
}

void stats_panel(const ViewerState& st) {
  const SessionFrame& f = st.frame;
  double sps = f.seconds > 0 ? f.spp / f.seconds : 0.0;
  double mrays = f.seconds > 0 ? double(f.counters.rays()) / f.seconds * 1e-6 : 0.0;
  ImGui::Text("%d x %d%s", f.width, f.height, f.preview ? "  (preview)" : "");
  ImGui::Text("spp %d   %.1f spp/s   %.2f Mrays/s", f.spp, sps, mrays);
  ImGui::Text("elapsed %.1f s   threads %d", f.seconds, st.render_threads());
  if (st.offload)
    for (const RankContribution& c : st.offload->contributions())
      ImGui::Text("rank %d: spp %d   %.1f spp/s", c.rank, c.spp, c.spp_per_s());
  convergence_stats(st);
  compare_stats(st);
  ImGui::Text("non-finite samples %llu", (unsigned long long)f.counters.nonfinite_samples);
  if (st.params.light_sampling == LightSampling::automatic && std::isfinite(f.auto_first_spread)) {
    // What automatic light sampling chose for this scene and camera (render/auto_light_sampling.h).
    if (!std::isfinite(f.auto_pilot_gain))
      ImGui::TextDisabled("auto light sampling: no planar light to choose for");
    else
      ImGui::TextWrapped("auto light sampling: first vertex %s (pilot gain %.2g)",
                  f.auto_first_spread <= kAutoMinSpread ? "by solid angle" : "by area", f.auto_pilot_gain);
  }
  if (!st.restart_latency_ms.empty())
    ImGui::Text("restart latency p50 %.1f ms  p95 %.1f ms", percentile(st.restart_latency_ms, 0.5),
                percentile(st.restart_latency_ms, 0.95));
  ImGui::Text("UI %.0f fps", ImGui::GetIO().Framerate);
}

}  // namespace

void draw_panels(ViewerState& st, PanelState& ps, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(width, height));
  ImGui::Begin("ptview", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                      ImGuiWindowFlags_NoTitleBar);
  ImGui::PushItemWidth(width * 0.55f);
  // The status line heads the column: what a click started or refused (a save, a load, a display mode) is seen
  // whichever panels are open.
  if (!st.status.empty()) ImGui::TextWrapped("%s", st.status.c_str());
  if (!st.earlier_messages.empty() &&
      ImGui::TreeNode("earlier", "earlier messages (%zu)", st.earlier_messages.size())) {
    for (auto m = st.earlier_messages.rbegin(); m != st.earlier_messages.rend(); ++m)
      ImGui::TextWrapped("%s", m->c_str());
    ImGui::TreePop();
  }
  if (ImGui::CollapsingHeader("Render", ImGuiTreeNodeFlags_DefaultOpen)) render_panel(st, ps);
  if (ImGui::CollapsingHeader("Camera")) camera_panel(st);
  if (ps.open_material) {
    ImGui::SetNextItemOpen(true);
    ps.open_material = false;
  }
  if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen)) material_panel(st);
  if (ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) light_panel(st);
  if (ImGui::CollapsingHeader("Scene", st.loading.valid() ? ImGuiTreeNodeFlags_DefaultOpen : 0)) scene_panel(st, ps);
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) display_panel(st);
  if (ImGui::CollapsingHeader("Compare", st.compare ? ImGuiTreeNodeFlags_DefaultOpen : 0)) compare_panel(st);
  if (ImGui::CollapsingHeader("Stats", ImGuiTreeNodeFlags_DefaultOpen)) stats_panel(st);
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace pt
