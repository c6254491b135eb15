#include "view/viewer_state.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "render/camera.h"
#include "render/trace_stats_json.h"
#include "scene/load.h"

namespace pt {

void ViewerState::restart() {
  auto rs = std::make_shared<RenderScene>(make_render_scene(scene, geo));
  render_scene = rs;
  session->set_preview_divisor(preview_div);
  uint64_t e = session->restart(rs, params);
  restart_started[e] = Clock::now();
  while (restart_started.size() > 64) restart_started.erase(restart_started.begin());
}

void ViewerState::start_load(const std::string& path) {
  if (loading.valid()) return;
  loading_path = path;
  status = "loading " + path + " ...";
  loading = std::async(std::launch::async, [path]() -> Result<LoadedScene> {
    auto t0 = Clock::now();
    Result<Scene> s = load_scene(path);
    if (!s) return Error{s.error()};
    LoadedScene out;
    out.geo = make_render_geometry(*s);
    out.scene = std::move(*s);
    out.load_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return out;
  });
}

bool ViewerState::poll_load() {
  if (!loading.valid() || loading.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
  Result<LoadedScene> r = loading.get();
  if (!r) {
    status = r.error();
    return false;
  }
  scene = std::move(r->scene);
  geo = std::move(r->geo);
  load_ms = r->load_ms;
  home_camera = *scene.camera;
  selected_material = -1;
  status = "loaded " + loading_path;
  restart();
  return true;
}

int ViewerState::pick(int x, int y) const {
  if (!render_scene) return -1;
  CameraRig rig = make_camera_rig(render_scene->camera, params.width, params.height);
  Ray ray = generate_camera_ray(rig, x, y, vec2(0.5f));
  Hit hit;
  if (!intersect_closest(render_scene->trace(), ray, hit)) return -1;
  const RenderGeometry& g = *render_scene->geo;
  if (hit.prim < g.triangle_count()) return int(g.tri_material[hit.prim]);
  return int(g.sphere_material[hit.prim - g.triangle_count()]);
}

int ViewerState::light_quad() const {
  for (size_t i = 0; i < scene.quads.size(); ++i) {
    uint32_t m = scene.quads[i].material;
    if (m < scene.materials.size() && scene.materials[m].emissive()) return int(i);
  }
  return -1;
}

void ViewerState::set_light_size(float width, float height) {
  int q = light_quad();
  if (q < 0 || !(width > 0.0f) || !(height > 0.0f)) return;
  Quad& quad = scene.quads[size_t(q)];
  vec3 center = quad.corner + 0.5f * (quad.edge1 + quad.edge2);
  quad.edge1 = glm::normalize(quad.edge1) * width;
  quad.edge2 = glm::normalize(quad.edge2) * height;
  quad.corner = center - 0.5f * (quad.edge1 + quad.edge2);
  geo = update_quads(*geo, scene);
  restart();
}

void ViewerState::save_current(const std::string& path) {
  Image copy = frame.image;
  saves.push_back(std::async(std::launch::async, [path, copy = std::move(copy)]() { return save_image(path, copy); }));
  status = "saving " + path;
}

namespace {
double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t i = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  return v[i];
}
}  // namespace

std::string ViewerState::stats_json() const {
  const RenderCounters& c = frame.counters;
  double elapsed = std::chrono::duration<double>(Clock::now() - start_time).count();
  nlohmann::json j;
  j["scene"] = scene.source;
  j["width"] = frame.width;
  j["height"] = frame.height;
  j["frames"] = frame.frames;
  j["spp"] = frame.spp;
  j["seconds"] = frame.seconds;
  j["rays"] = c.rays();
  j["mrays_per_s"] = frame.seconds > 0 ? double(c.rays()) / frame.seconds * 1e-6 : 0.0;
  j["spp_per_s"] = frame.seconds > 0 ? frame.spp / frame.seconds : 0.0;
  j["nonfinite_samples"] = c.nonfinite_samples;
  j["epoch"] = frame.epoch;
  j["threads"] = session ? session->thread_count() : 0;
  if (render_scene) {
    const TraceGeometry& t = render_scene->trace();
    j["triangles"] = render_scene->triangle_count();
    j["bvh"] = trace_stats_json(t);
  }
  j["skipped"] = nlohmann::json::object();
  for (const auto& [name, count] : skipped_work(c)) j["skipped"][name] = count;
  j["restart_latency_ms"] = {{"p50", percentile(restart_latency_ms, 0.5)},
                             {"p95", percentile(restart_latency_ms, 0.95)},
                             {"count", restart_latency_ms.size()}};
  j["ui_fps"] = elapsed > 0 ? double(ui_frames) / elapsed : 0.0;
  j["ui_frames"] = ui_frames;
  j["load_ms"] = load_ms;
  j["warnings"] = scene.warnings;
  return j.dump(2) + "\n";
}

}  // namespace pt
