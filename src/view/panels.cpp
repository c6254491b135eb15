#include "view/panels.h"

#include <imgui.h>

#include <algorithm>

namespace pt {

namespace {

bool input_text(const char* label, std::string& s) {
  char buf[1024];
  std::snprintf(buf, sizeof buf, "%s", s.c_str());
  bool changed = ImGui::InputText(label, buf, sizeof buf);
  if (changed) s = buf;
  return changed;
}

bool drag_vec3(const char* label, vec3& v, float speed) { return ImGui::DragFloat3(label, &v.x, speed, 0, 0, "%.3f"); }

void render_panel(ViewerState& st, PanelState& ps) {
  bool changed = false;
  int integrator = int(st.params.integrator);
  changed |= ImGui::Combo("integrator", &integrator, "mis\0nee\0bsdf\0auto\0");
  st.params.integrator = IntegratorKind(integrator);
  int ls = int(st.params.light_sampling);
  changed |= ImGui::Combo("light sampling", &ls, "area\0solid angle\0");
  st.params.light_sampling = LightSampling(ls);
  int sampler = int(st.params.sampler);
  changed |= ImGui::Combo("sampler", &sampler, "independent\0sobol\0");
  st.params.sampler = SamplerKind(sampler);
  changed |= ImGui::SliderInt("max depth", &st.params.max_depth, 0, 256);
  changed |= ImGui::SliderInt("spp / frame", &st.params.spp_per_frame, 1, 64);
  int threads = st.params.threads > 0 ? st.params.threads : st.session->thread_count();
  if (ImGui::SliderInt("threads", &threads, 1, 64)) {
    st.params.threads = threads;
    changed = true;
  }
  if (changed) st.restart();
  bool paused = st.session->paused();
  if (ImGui::Checkbox("pause", &paused)) st.session->set_paused(paused);
  ImGui::SameLine();
  if (ImGui::Button("restart")) st.restart();
  if (ImGui::InputInt("stop at spp", &ps.target_spp)) {
    ps.target_spp = std::max(0, ps.target_spp);
    st.session->set_target_spp(ps.target_spp);
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("0: never stop");
  input_text("file", ps.save_path);
  if (ImGui::Button("save image")) {
    if (is_supported_image_extension(ps.save_path)) st.save_current(ps.save_path);
    else st.status = ps.save_path + ": use .png, .exr or .pfm";
  }
  ImGui::SameLine();
  ImGui::TextDisabled(".png .exr .pfm");
}

void camera_panel(ViewerState& st) {
  Camera& c = *st.scene.camera;
  bool changed = drag_vec3("eye", c.eye, 0.01f);
  changed |= drag_vec3("target", c.target, 0.01f);
  changed |= ImGui::SliderFloat("fov", &c.fov_deg, 5.0f, 120.0f, "%.1f deg");
  float dist = glm::length(c.eye - c.target);
  if (ImGui::DragFloat("orbit distance", &dist, 0.01f, 1e-3f, 1e6f)) {
    c.eye = c.target + glm::normalize(c.eye - c.target) * dist;
    changed = true;
  }
  if (ImGui::Button("reset camera (R)")) {
    c = st.home_camera;
    changed = true;
  }
  if (changed && glm::length(c.eye - c.target) > 0.0f) st.restart();
}

void material_panel(ViewerState& st) {
  if (st.scene.materials.empty()) return;
  std::string current = st.selected_material >= 0 ? st.scene.materials[size_t(st.selected_material)].name : "(click the image)";
  if (ImGui::BeginCombo("material", current.c_str())) {
    for (size_t i = 0; i < st.scene.materials.size(); ++i) {
      std::string label = st.scene.materials[i].name.empty() ? "#" + std::to_string(i) : st.scene.materials[i].name;
      if (ImGui::Selectable((label + "##" + std::to_string(i)).c_str(), int(i) == st.selected_material))
        st.selected_material = int(i);
    }
    ImGui::EndCombo();
  }
  if (st.selected_material < 0) return;
  Material& m = st.scene.materials[size_t(st.selected_material)];
  bool changed = false;
  int type = int(m.type);
  if (ImGui::Combo("type", &type, "diffuse\0specular\0glass\0")) {
    m.type = MaterialType(type);
    if (m.type == MaterialType::glass) m.albedo = vec3(1.0f);
    changed = true;
  }
  if (m.type != MaterialType::glass) changed |= ImGui::ColorEdit3("albedo", &m.albedo.x);
  else changed |= ImGui::SliderFloat("ior", &m.ior, 1.0f, 3.0f);
  changed |= ImGui::ColorEdit3("emission", &m.emission.x, ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_Float);
  if (changed) {
    m.albedo = glm::clamp(m.albedo, vec3(0.0f), vec3(1.0f));
    m.emission = glm::max(m.emission, vec3(0.0f));
    st.restart();
  }
}

void light_panel(ViewerState& st) {
  int q = st.light_quad();
  if (q < 0) {
    ImGui::TextDisabled("no rectangle light in this scene");
    return;
  }
  Quad& quad = st.scene.quads[size_t(q)];
  Material& m = st.scene.materials[quad.material];
  float w = glm::length(quad.edge1), h = glm::length(quad.edge2);
  float size[2] = {w, h};
  if (ImGui::DragFloat2("size", size, 0.005f, 1e-4f, 1e4f, "%.3f")) st.set_light_size(size[0], size[1]);
  float intensity = max_component(m.emission);
  vec3 color = intensity > 0.0f ? m.emission / intensity : vec3(1.0f);
  bool changed = ImGui::ColorEdit3("color", &color.x);
  changed |= ImGui::DragFloat("intensity", &intensity, 0.1f, 0.0f, 1e6f);
  if (changed) {
    m.emission = glm::max(color, vec3(0.0f)) * std::max(intensity, 0.0f);
    st.restart();
  }
  vec3 center = quad.corner + 0.5f * (quad.edge1 + quad.edge2);
  if (drag_vec3("position", center, 0.01f)) {
    quad.corner = center - 0.5f * (quad.edge1 + quad.edge2);
    st.geo = update_quads(*st.geo, st.scene);
    st.restart();
  }
}

void scene_panel(ViewerState& st, PanelState& ps) {
  ImGui::TextWrapped("%s", st.scene.source.c_str());
  input_text("path", ps.open_path);
  if (ImGui::Button("open OBJ / JSON") && !ps.open_path.empty()) st.start_load(ps.open_path);
  ImGui::SameLine();
  ImGui::TextDisabled("(or drop a file)");
  if (st.loading.valid()) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "loading %s ...", st.loading_path.c_str());
  if (st.render_scene) {
    const TraceGeometry& t = st.render_scene->trace();
    ImGui::Text("triangles %u  spheres %zu  lights %zu", st.render_scene->triangle_count(), st.render_scene->geo->spheres.size(),
                st.render_scene->lights.lights.size());
    ImGui::Text("BVH8 nodes %zu  blocks %zu  build %.1f ms", t.triangles.node_count, t.triangles.block_count,
                t.stats.build_ms);
  }
  if (!st.status.empty()) ImGui::TextWrapped("%s", st.status.c_str());
  for (const std::string& w : st.scene.warnings) ImGui::TextColored(ImVec4(1, 0.7f, 0.3f, 1), "%s", w.c_str());
}

void display_panel(ViewerState& st) {
  ImGui::SliderFloat("exposure", &st.display.exposure, -8.0f, 8.0f, "%.2f stops");
  int tm = int(st.display.tonemap);
  if (ImGui::Combo("tonemap", &tm, "clamp\0Reinhard\0ACES\0")) st.display.tonemap = Tonemap(tm);
}

void stats_panel(const ViewerState& st) {
  const SessionFrame& f = st.frame;
  double sps = f.seconds > 0 ? f.spp / f.seconds : 0.0;
  double mrays = f.seconds > 0 ? double(f.counters.rays()) / f.seconds * 1e-6 : 0.0;
  ImGui::Text("%d x %d%s", f.width, f.height, f.preview ? "  (preview)" : "");
  ImGui::Text("spp %d   %.1f spp/s   %.2f Mrays/s", f.spp, sps, mrays);
  ImGui::Text("elapsed %.1f s   threads %d", f.seconds, st.session->thread_count());
  ImGui::Text("non-finite samples %llu", (unsigned long long)f.counters.nonfinite_samples);
  std::vector<double> lat = st.restart_latency_ms;
  std::sort(lat.begin(), lat.end());
  if (!lat.empty())
    ImGui::Text("restart latency p50 %.1f ms  p95 %.1f ms", lat[lat.size() / 2], lat[std::min(lat.size() - 1, lat.size() * 95 / 100)]);
  ImGui::Text("UI %.0f fps", ImGui::GetIO().Framerate);
}

}  // namespace

void draw_panels(ViewerState& st, PanelState& ps, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(width, height));
  ImGui::Begin("ptview", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                      ImGuiWindowFlags_NoTitleBar);
  ImGui::PushItemWidth(width * 0.55f);
  if (ImGui::CollapsingHeader("Render", ImGuiTreeNodeFlags_DefaultOpen)) render_panel(st, ps);
  if (ImGui::CollapsingHeader("Camera")) camera_panel(st);
  if (ps.open_material) {
    ImGui::SetNextItemOpen(true);
    ps.open_material = false;
  }
  if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen)) material_panel(st);
  if (ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) light_panel(st);
  if (ImGui::CollapsingHeader("Scene")) scene_panel(st, ps);
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) display_panel(st);
  if (ImGui::CollapsingHeader("Stats", ImGuiTreeNodeFlags_DefaultOpen)) stats_panel(st);
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace pt
