#include "view/viewer_state.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/camera.h"
#include "render/image_error.h"
#include "render/names.h"
#include "render/stats_json.h"
#include "scene/load.h"
#include "scene/save_json.h"
#include "view/camera_control.h"

namespace pt {

namespace {

/// The one normalization of an edited material (panel and script alike).
Material normalized(Material m) {
  m.albedo = info_of(m.type).uses_albedo ? glm::clamp(m.albedo, vec3(0.0f), vec3(1.0f)) : vec3(1.0f);
  m.emission = glm::max(m.emission, vec3(0.0f));
  if (!is_finite(m.emission)) m.emission = vec3(0.0f);
  if (!(m.ior >= 1.0f) || !std::isfinite(m.ior)) m.ior = 1.0f;
  return m;
}

bool valid_camera(const Camera& c) {
  return is_finite(c.eye) && is_finite(c.target) && is_finite(c.up) && camera_distance(c) > 0.0f && c.fov_deg > 0.0f &&
         c.fov_deg < 180.0f;
}

}  // namespace

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t i = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  return v[i];
}

void ViewerState::init(Scene s, const RenderParams& p, const DisplaySettings& d, int threads) {
  params = p;
  display = d;
  home_camera = s.camera.value_or(Camera{});
  geo = make_render_geometry(s);
  ++geometry_builds;
  scene = std::move(s);
  loaded_materials = scene.materials;
  lights = find_scene_lights(scene);
  render_scene = std::make_shared<RenderScene>(make_render_scene(scene, geo, AutoPilot::deferred));
  if (threads >= 0) {
    session = std::make_unique<RenderSession>(threads);
    session->set_adaptive(adaptive);
    session->set_publish_counts(offload != nullptr);
  }
  restart();
}

void ViewerState::restart() {
  ++restarts;
  if (!session) return;
  if (compare && session_b) {
    // Side A's time slice comes first: side B waits from its first frame (its preview still renders), so neither
    // side renders beyond its slice while the restart sets up the other.
    slice_b = false;
    slice_start = Clock::now();
    set_paused(paused);
    session_b->set_preview_divisor(preview_div);
    session_b->set_adaptive(compare->adaptive);
    session_b->restart(render_scene, params_b());
  }
  session->set_preview_divisor(preview_div);
  uint64_t e = session->restart(render_scene, params);
  if (offload) offload->post_epoch(e, params, scene, geometry_builds, geometry_refits);
  restart_started[e] = Clock::now();
  while (restart_started.size() > 64) restart_started.erase(restart_started.begin());
}

Tier ViewerState::commit(Tier tier) {
  switch (tier) {
    case Tier::none:
    case Tier::display:
    case Tier::sampling: return tier;
    case Tier::camera: {
      auto rs = std::make_shared<RenderScene>(*render_scene);
      rs->camera = scene.camera.value_or(Camera{});
      rs->camera.eye = to_render_point(*geo, rs->camera.eye);
      rs->camera.target = to_render_point(*geo, rs->camera.target);
      rs->auto_pilot_pending = true;  // the pilot looks through the camera; the session runs it
      render_scene = std::move(rs);
      break;
    }
    case Tier::light_refit:
      geo = refit_render_geometry(*geo, scene);
      ++geometry_refits;
      [[fallthrough]];
    case Tier::material:
    case Tier::rebuild: {
      render_scene = std::make_shared<RenderScene>(make_render_scene(scene, geo, AutoPilot::deferred));
      std::vector<SceneLight> found =
          tier == Tier::rebuild ? find_scene_lights(scene) : find_scene_lights(scene, lights);
      if (tier == Tier::rebuild || found.size() != lights.size()) {
        lights = std::move(found);
        if (selected_light >= int(lights.size())) selected_light = -1;
      }
      break;
    }
  }
  restart();
  return tier;
}

Tier ViewerState::apply(const Edit& edit) {
  struct V {
    ViewerState& st;
    Tier operator()(const CameraEdit& e) const {
      if (!valid_camera(e.camera) || st.scene.camera == e.camera) return Tier::none;
      st.scene.camera = e.camera;
      return Tier::camera;
    }
    Tier operator()(const RenderParamsEdit& e) const {
      if (e.params == st.params) return Tier::none;
      st.params = e.params;
      return Tier::camera;
    }
    Tier operator()(const DisplayEdit& e) const {
      st.display = e.display;
      return Tier::display;
    }
    Tier operator()(const DisplayModeEdit& e) const {
      if (e.mode == DisplayMode::reference_error && !st.reference) return Tier::none;
      st.display_mode = e.mode;
      st.display_dirty = true;
      if (st.session) st.session->set_publish_maps(needs_maps(e.mode));
      if (st.session_b) st.session_b->set_publish_maps(needs_maps(e.mode));
      return Tier::display;
    }
    Tier operator()(const AdaptiveEdit& e) const {
      AdaptiveParams a = e.adaptive;
      if (!std::isfinite(a.noise_threshold) || a.noise_threshold < 0.0 || a.noise_threshold > 1.0 || a.min_spp < 0)
        return Tier::none;
      if (a.noise_threshold == st.adaptive.noise_threshold && a.min_spp == st.adaptive.min_spp) return Tier::none;
      st.adaptive = a;
      if (st.session) st.session->set_adaptive(a);
      return Tier::sampling;
    }
    Tier operator()(const StopEdit& e) const {
      if (e.spp < 0 || e.spp == st.target_spp) return Tier::none;
      st.target_spp = e.spp;
      if (st.session) st.session->set_target_spp(e.spp);
      if (st.session_b) st.session_b->set_target_spp(e.spp);
      return Tier::sampling;
    }
    Tier operator()(const CompareEdit& e) const {
      if (!e.b) {
        if (!st.compare) return Tier::none;
        st.compare.reset();
        if (st.session_b) st.session_b->set_paused(true);
        if (st.session) st.session->set_paused(st.paused);
        return Tier::display;
      }
      const AdaptiveParams& a = e.b->adaptive;
      if (!std::isfinite(a.noise_threshold) || a.noise_threshold < 0.0 || a.noise_threshold > 1.0 || a.min_spp < 0)
        return Tier::none;
      if (st.compare && *st.compare == *e.b) return Tier::none;
      st.compare = e.b;
      if (st.session && !st.session_b) {
        st.session_b = std::make_unique<RenderSession>(st.session->thread_count());
        st.session_b->set_target_spp(st.target_spp);  // "stop at spp" holds for both sides
      }
      if (st.session_b) st.session_b->set_publish_maps(needs_maps(st.display_mode));
      st.frame_b = SessionFrame{};
      st.display_dirty = true;
      return Tier::camera;  // both sides start together
    }
    Tier operator()(const DividerEdit& e) const {
      if (!std::isfinite(e.x)) return Tier::none;
      st.divider = std::clamp(e.x, 0.0f, 1.0f);
      return Tier::display;
    }
    Tier operator()(const MaterialEdit& e) const {
      if (e.index < 0 || size_t(e.index) >= st.scene.materials.size()) return Tier::none;
      return st.set_material(size_t(e.index), e.material);
    }
    Tier operator()(const LightShapeEdit& e) const {
      if (e.light < 0 || size_t(e.light) >= st.lights.size()) return Tier::none;
      SceneLight& l = st.lights[size_t(e.light)];
      // A size, factor or centre that is the light's already changes nothing (resizing and scaling keep the centre).
      const LightPlacement was = light_placement(st.scene, l);
      bool changed = false;
      if (e.size && *e.size != was.size) changed |= resize_light(st.scene, l, *e.size);
      if (e.scale && *e.scale != 1.0f) changed |= scale_light(st.scene, l, *e.scale);
      if (e.center && is_finite(*e.center) && *e.center != was.center) {
        move_light(st.scene, l, *e.center);
        changed = true;
      }
      return changed ? Tier::light_refit : Tier::none;
    }
    Tier operator()(const LightEmissionEdit& e) const {
      if (e.light < 0 || size_t(e.light) >= st.lights.size()) return Tier::none;
      const uint32_t index = st.lights[size_t(e.light)].material;
      Material m = st.scene.materials[index];
      m.emission = glm::max(e.color, vec3(0.0f)) * std::max(e.intensity, 0.0f);
      return st.set_material(index, m);
    }
    Tier operator()(const SceneEdit& e) const {
      if (!e.loaded) return Tier::none;
      st.scene = std::move(e.loaded->scene);
      st.geo = std::move(e.loaded->geo);
      st.load_ms = e.loaded->load_ms;
      st.loaded_materials = st.scene.materials;
      st.home_camera = st.scene.camera.value_or(Camera{});
      st.selected_material = st.selected_light = -1;
      ++st.geometry_builds;  // built off the UI thread, by start_load
      return Tier::rebuild;
    }
    Tier operator()(const RestartEdit&) const { return Tier::camera; }
  };
  return commit(std::visit(V{*this}, edit));
}

Tier ViewerState::set_material(size_t index, const Material& m) {
  Material& current = scene.materials[index];
  const Material n = normalized(m);
  if (n == current) return Tier::none;
  current = n;
  return Tier::material;
}

void ViewerState::say(std::string message) {
  if (!status.empty()) earlier_messages.push_back(std::move(status));
  if (earlier_messages.size() > kEarlierMessages) earlier_messages.pop_front();
  status = std::move(message);
}

void ViewerState::start_load(const std::string& path) {
  if (loading.valid()) return;
  loading_path = path;
  say("loading " + path + " ...");
  load_progress = std::make_shared<LoadProgress>();
  loading = std::async(std::launch::async, [path, progress = load_progress]() -> Result<LoadedScene> {
    Result<Scene> s = load_scene(path);
    if (!s) return Error{s.error()};
    progress->triangles = s->triangle_count();
    progress->stage = 1;
    LoadedScene out;
    out.geo = make_render_geometry(*s);
    out.scene = std::move(*s);
    out.load_ms = std::chrono::duration<double, std::milli>(Clock::now() - progress->started).count();
    return out;
  });
}

bool ViewerState::poll_load() {
  if (!loading.valid() || loading.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
  Result<LoadedScene> r = loading.get();
  load_progress.reset();
  if (!r) {
    say(r.error());
    return false;
  }
  say("loaded " + loading_path);
  apply(SceneEdit{std::make_shared<LoadedScene>(std::move(*r))});
  return true;
}

ViewerState::PickResult ViewerState::pick(int x, int y) const {
  PickResult out;
  if (!render_scene) return out;
  CameraRig rig = make_camera_rig(render_scene->camera, params.width, params.height);
  Ray ray = generate_camera_ray(rig, x, y, vec2(0.5f));
  Hit hit;
  if (!intersect_closest(render_scene->trace(), ray, hit)) return out;
  out.material = int(primitive_material(*render_scene->geo, hit.prim));
  out.light = light_of_primitive(scene, lights, hit.prim);
  return out;
}

bool ViewerState::select_at(int x, int y) {
  PickResult p = pick(x, y);
  selected_material = p.material;
  if (p.light >= 0) selected_light = p.light;
  return p.material >= 0;
}

void ViewerState::save_current(const std::string& path) {
  Image copy = frame.image;
  saves.push_back(
      {path, std::async(std::launch::async, [path, copy = std::move(copy)] { return save_image(path, copy); })});
  say("saving " + path);
}

void ViewerState::poll_saves(bool wait) {
  size_t done = 0;
  for (; done < saves.size(); ++done) {
    PendingSave& s = saves[done];
    if (!wait && s.result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) break;
    std::optional<Error> err = s.result.get();
    say(err ? err->message : "saved " + s.path);
    if (err) save_errors.push_back(std::move(*err));
  }
  saves.erase(saves.begin(), saves.begin() + std::ptrdiff_t(done));
}

std::optional<Error> ViewerState::save_scene(const std::string& path) {
  std::optional<Error> err = save_scene_json(scene, loaded_materials, path);
  say(err ? err->message : "saved " + path);
  return err;
}

RenderParams ViewerState::params_b() const {
  RenderParams p = params;
  if (compare) {
    p.integrator = compare->integrator;
    p.light_sampling = compare->light_sampling;
    p.sampler = compare->sampler;
  }
  return p;
}

void ViewerState::set_paused(bool p) {
  paused = p;
  if (offload) offload->set_hold(p);
  if (session) session->set_paused(p || (compare && slice_b));
  if (session_b) session_b->set_paused(p || !compare || !slice_b);
}

void ViewerState::tick_compare() {
  if (!compare || !session_b || paused) return;
  if (std::chrono::duration<double>(Clock::now() - slice_start).count() >= kCompareSliceSeconds) {
    slice_b = !slice_b;
    slice_start = Clock::now();
  }
  if (session->paused() != slice_b) session->set_paused(slice_b);
  if (session_b->paused() != !slice_b) session_b->set_paused(!slice_b);
}

double ViewerState::rel_mse_to_reference(const SessionFrame& f) const {
  const bool comparable =
      reference && !f.preview && f.image.width == reference->width && f.image.height == reference->height;
  return comparable ? compare_images(f.image, *reference).rel_mse : std::numeric_limits<double>::quiet_NaN();
}

void ViewerState::note_frame_b() { frame_b_rel_mse = rel_mse_to_reference(frame_b); }

bool ViewerState::fetch_frame() {
  const bool fresh = offload ? offload->fetch(*session, frame) : session->fetch(frame);
  if (fresh) note_frame();
  return fresh;
}

bool ViewerState::fetch_frame_b() {
  const bool fresh = session_b && session_b->fetch(frame_b);
  if (fresh) note_frame_b();
  return fresh;
}

void ViewerState::note_frame() {
  if (!error_history.empty() && (frame.seconds < error_history.back().first || frame.preview)) error_history.clear();
  if (!frame.preview && frame.seconds > 0 && std::isfinite(frame.est_rel_mse) && frame.est_rel_mse > 0)
    error_history.emplace_back(frame.seconds, frame.est_rel_mse);
  if (error_history.size() > 4096) error_history.erase(error_history.begin(), error_history.begin() + 2048);
  frame_rel_mse = rel_mse_to_reference(frame);
}



int ViewerState::render_threads() const {
  return frame.threads > 0 ? frame.threads : session ? session->thread_count() : 0;
}

std::string ViewerState::stats_json() const {
  double elapsed = std::chrono::duration<double>(Clock::now() - start_time).count();
  RunSummary run;
  run.frames = frame.frames;
  run.spp = frame.spp;
  run.seconds = frame.seconds;
  run.load_ms = load_ms;
  run.counters = frame.counters;
  run.threads = render_threads();
  run.epoch = frame.epoch;
  run.convergence.est_rel_mse = frame.preview ? std::numeric_limits<double>::quiet_NaN() : frame.est_rel_mse;
  run.convergence.converged_fraction = frame.converged_fraction;
  run.convergence.spp = frame.spp_stats;
  if (adaptive.enabled()) {
    run.convergence.noise_threshold = adaptive.noise_threshold;
    run.convergence.min_spp = effective_min_spp(adaptive);
  }
  if (offload)
    for (const RankContribution& c : offload->contributions()) run.per_rank.push_back({c.spp, c.seconds});
  RenderParams shown = params;
  shown.width = frame.width;
  shown.height = frame.height;
  nlohmann::json j = make_stats_json(shown, scene, *render_scene, run);
  j["restart_latency_ms"] = {{"p50", percentile(restart_latency_ms, 0.5)},
                             {"p95", percentile(restart_latency_ms, 0.95)},
                             {"count", restart_latency_ms.size()}};
  if (offload)  // spp/s of each rank in the shown epoch, as the Stats panel shows it
    for (size_t i = 0; i < j["per_rank"].size(); ++i) {
      const RankWork& w = run.per_rank[i];
      j["per_rank"][i]["spp_per_s"] = w.seconds > 0 ? w.spp / w.seconds : 0.0;
    }
  j["ui_fps"] = elapsed > 0 ? double(ui_frames) / elapsed : 0.0;
  j["ui_frames"] = ui_frames;
  j["restarts"] = restarts;
  j["geometry_builds"] = geometry_builds;
  j["geometry_refits"] = geometry_refits;
  j["display_mode"] = name_of<DisplayMode>(kDisplayModeNames, display_mode);
  if (compare) {
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    auto side = [&](const SessionFrame& f, double rel) {
      return nlohmann::json{{"spp", f.spp},
                            {"seconds", f.seconds},
                            {"est_rel_mse", num(f.preview ? std::numeric_limits<double>::quiet_NaN() : f.est_rel_mse)},
                            {"rel_mse", num(rel)}};
    };
    j["compare"] = {{"a", side(frame, frame_rel_mse)}, {"b", side(frame_b, frame_b_rel_mse)}};
    j["compare"]["b"]["integrator"] = name_of(compare->integrator);
    j["compare"]["b"]["light_sampling"] = name_of(compare->light_sampling);
    j["compare"]["b"]["sampler"] = name_of(compare->sampler);
    j["compare"]["b"]["noise_threshold"] = compare->adaptive.noise_threshold;
  }
  if (reference) {
    double rel = true_rel_mse();
    j["rel_mse"] = std::isfinite(rel) ? nlohmann::json(rel) : nlohmann::json(nullptr);
  }
  return j.dump(2) + "\n";
}

}  // namespace pt
