#include "view/script.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <variant>

#include "core/read_file.h"
#include "render/names.h"
#include "view/camera_control.h"
#include "view/viewer_state.h"

namespace pt {

namespace {

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v);
}

float num(const ScriptCommand& c, size_t i) { return std::stof(c.args[i]); }
/// A count or a pixel, read in double (a float rounds whole numbers past 2^24: wait-spp 16777217 waited for one
/// sample less) and clamped to int's range (a pixel far off the image is off it, not undefined behaviour).
int whole(const ScriptCommand& c, size_t i) {
  const double v = std::strtod(c.args[i].c_str(), nullptr);
  constexpr double lo = std::numeric_limits<int>::min(), hi = std::numeric_limits<int>::max();
  return std::isnan(v) ? 0 : int(std::clamp(v, lo, hi));
}

void fail(ScriptRun& r, const ScriptCommand& c, const std::string& why) {
  std::fprintf(stderr, "ptview: %s:%d: %s\n", r.file.c_str(), c.line, why.c_str());
  ++r.failures;
}

std::string check_none(const std::vector<std::string>&) { return {}; }

std::string check_count(const std::vector<std::string>& a) {
  double v = std::strtod(a[0].c_str(), nullptr);
  return v >= 0 && v == std::floor(v) && v <= 1e9 ? "" : "'" + a[0] + "' is not a non-negative integer";
}

std::string check_positive(const std::vector<std::string>& a) {
  for (const std::string& s : a)
    if (!(std::strtod(s.c_str(), nullptr) > 0)) return "'" + s + "' is not positive";
  return {};
}

/// "r,g,b" or "x" values of a key=value argument.
bool parse_values(const std::string& s, std::vector<float>& out) {
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, ',');) {
    if (!is_number(part)) return false;
    out.push_back(std::stof(part));
  }
  return !s.empty() && s.back() != ',';
}

std::string check_material(const std::vector<std::string>& a) {
  if (!value_of<MaterialType>(kMaterialTypeNames, a[0]))
    return "unknown material type '" + a[0] + "' (expected " + names_list<MaterialType>(kMaterialTypeNames) + ")";
  for (size_t k = 1; k < a.size(); ++k) {
    size_t eq = a[k].find('=');
    std::string key = a[k].substr(0, eq);
    if (eq == std::string::npos || (key != "albedo" && key != "ior" && key != "emission"))
      return "expected albedo=r,g,b, ior=x or emission=r,g,b, got '" + a[k] + "'";
    std::vector<float> v;
    if (!parse_values(a[k].substr(eq + 1), v)) return "'" + a[k] + "': not a list of numbers";
    if (v.size() != (key == "ior" ? 1u : 3u)) return "'" + a[k] + "': wrong number of values";
  }
  return {};
}

std::string check_tonemap(const std::vector<std::string>& a) {
  return value_of<Tonemap>(kTonemapNames, a[0]) ? ""
                                                : "unknown tonemap '" + a[0] + "' (expected " +
                                                      names_list<Tonemap>(kTonemapNames) + ")";
}

std::string check_display_mode(const std::vector<std::string>& a) {
  return value_of<DisplayMode>(kDisplayModeNames, a[0]) ? ""
                                                        : "unknown display mode '" + a[0] + "' (expected " +
                                                              names_list<DisplayMode>(kDisplayModeNames) + ")";
}

std::string check_noise_threshold(const std::vector<std::string>& a) {
  double t = std::strtod(a[0].c_str(), nullptr);
  if (!(t >= 0.0 && t <= 1.0)) return "'" + a[0] + "': the threshold must be from 0 (off) to 1";
  if (a.size() > 1) {
    double m = std::strtod(a[1].c_str(), nullptr);
    if (!(m >= 0 && m == std::floor(m) && m <= (1 << 24)))
      return "'" + a[1] + "': the minimum spp must be an integer from 0 (automatic) to 16777216";
  }
  return {};
}

/// `compare off` or `compare key=value ...` over A's settings: integrator=, light-sampling=, sampler=,
/// adaptive=T|off. Returns the config, or the reason it is malformed.
std::variant<std::optional<CompareConfig>, std::string> parse_compare(const std::vector<std::string>& a,
                                                                      const RenderParams& base) {
  if (a.size() == 1 && a[0] == "off") return std::optional<CompareConfig>{};
  CompareConfig c{base.integrator, base.light_sampling, base.sampler, {}};
  for (const std::string& kv : a) {
    size_t eq = kv.find('=');
    std::string key = kv.substr(0, eq), value = eq == std::string::npos ? "" : kv.substr(eq + 1);
    if (key == "integrator" && value_of<IntegratorKind>(kIntegratorNames, value))
      c.integrator = *value_of<IntegratorKind>(kIntegratorNames, value);
    else if (key == "light-sampling" && value_of<LightSampling>(kLightSamplingNames, value))
      c.light_sampling = *value_of<LightSampling>(kLightSamplingNames, value);
    else if (key == "sampler" && value_of<SamplerKind>(kSamplerNames, value))
      c.sampler = *value_of<SamplerKind>(kSamplerNames, value);
    else if (key == "adaptive" && value == "off")
      c.adaptive = {};
    else if (key == "adaptive" && is_number(value) && std::strtod(value.c_str(), nullptr) > 0 &&
             std::strtod(value.c_str(), nullptr) <= 1)
      c.adaptive.noise_threshold = std::strtod(value.c_str(), nullptr);
    else
      return "'" + kv + "': expected off, integrator=" + names_list<IntegratorKind>(kIntegratorNames) +
             ", light-sampling=" + names_list<LightSampling>(kLightSamplingNames) + ", sampler=" +
             names_list<SamplerKind>(kSamplerNames) + " or adaptive=T|off (0 < T <= 1)";
  }
  return std::optional<CompareConfig>{c};
}

std::string check_compare(const std::vector<std::string>& a) {
  auto r = parse_compare(a, RenderParams{});
  return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : "";
}

std::string check_window_size(const std::vector<std::string>& a) {
  for (const std::string& s : a) {
    const double v = std::strtod(s.c_str(), nullptr);
    if (!(v >= 1 && v <= 16384 && v == std::floor(v))) return "'" + s + "' is not a window size from 1 to 16384";
  }
  return {};
}

/// `window W H`: asks the viewer for the size, then waits until the window has it and the render has followed the
/// image area (unless the size is locked), so that the next wait-frames waits for frames of the new size. The
/// window system may refuse a size: after 10 s the command fails instead of waiting for ever.
ScriptStep run_window(ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
  const int w = whole(c, 0), h = whole(c, 1);
  const auto now = std::chrono::steady_clock::now();
  if (!r.deadline) {
    r.deadline = now + std::chrono::seconds(10);
    r.window_request = std::array<int, 2>{w, h};
    return ScriptStep::wait;
  }
  const WindowView& v = r.window;
  const bool sized = v.window_w == w && v.window_h == h;
  const bool followed = v.size_locked || (st.params.width == v.follow_w && st.params.height == v.follow_h);
  if (sized && followed) {
    r.deadline.reset();
    return ScriptStep::done;
  }
  if (now < *r.deadline) return ScriptStep::wait;
  r.deadline.reset();
  fail(r, c,
       sized ? "window: the render stayed " + std::to_string(st.params.width) + "x" + std::to_string(st.params.height) +
                   ", the image area is " + std::to_string(v.follow_w) + "x" + std::to_string(v.follow_h)
             : "window: the window system kept the window at " + std::to_string(v.window_w) + "x" +
                   std::to_string(v.window_h));
  return ScriptStep::done;
}

std::string check_on_off(const std::vector<std::string>& a) {
  return a[0] == "on" || a[0] == "off" ? "" : "'" + a[0] + "' is neither on nor off";
}

std::string check_fraction(const std::vector<std::string>& a) {
  double v = std::strtod(a[0].c_str(), nullptr);
  return v >= 0.0 && v <= 1.0 ? "" : "'" + a[0] + "' is not a fraction from 0 to 1";
}

/// The camera commands: a copy of the camera moved, applied as a CameraEdit.
template <class F>
ScriptStep move_camera(ViewerState& st, F&& f) {
  Camera cam = st.scene.camera.value_or(Camera{});
  f(cam);
  st.apply(CameraEdit{cam});
  return ScriptStep::done;
}

/// The light the light-* commands act on: the selection, else the first light.
int target_light(ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
  if (st.lights.empty()) {
    fail(r, c, c.name + ": the scene has no light");
    return -1;
  }
  if (st.selected_light < 0) st.selected_light = 0;
  return st.selected_light;
}

const ScriptCommandSpec kCommands[] = {
    {"orbit", "DX DY", 2, 2, true, check_none,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       return move_camera(st, [&](Camera& cam) { orbit_camera(cam, num(c, 0), num(c, 1)); });
     }},
    {"pan", "DX DY", 2, 2, true, check_none,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       return move_camera(st, [&](Camera& cam) { pan_camera(cam, num(c, 0), num(c, 1)); });
     }},
    {"dolly", "F", 1, 1, true, check_positive,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       return move_camera(st, [&](Camera& cam) { dolly_camera(cam, num(c, 0), camera_min_distance(st.geo.get())); });
     }},
    {"pick", "X Y", 2, 2, true, check_none,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       if (!st.select_at(whole(c, 0), whole(c, 1))) fail(r, c, "pick: no object under that pixel");
       return ScriptStep::done;
     }},
    {"set-material", "TYPE [albedo=r,g,b] [ior=x] [emission=r,g,b]", 1, 4, false, check_material,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       if (st.selected_material < 0) {
         fail(r, c, "set-material: nothing picked");
         return ScriptStep::done;
       }
       Material m = st.scene.materials[size_t(st.selected_material)];
       m.type = *value_of<MaterialType>(kMaterialTypeNames, c.args[0]);
       for (size_t k = 1; k < c.args.size(); ++k) {
         size_t eq = c.args[k].find('=');
         std::string key = c.args[k].substr(0, eq);
         std::vector<float> v;
         parse_values(c.args[k].substr(eq + 1), v);
         if (key == "ior") m.ior = v[0];
         else if (key == "albedo") m.albedo = vec3(v[0], v[1], v[2]);
         else m.emission = vec3(v[0], v[1], v[2]);
       }
       st.apply(MaterialEdit{st.selected_material, m});
       return ScriptStep::done;
     }},
    {"light", "N", 1, 1, true, check_count,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       int n = whole(c, 0);
       if (n >= int(st.lights.size()))
         fail(r, c, "light: the scene has " + std::to_string(st.lights.size()) + " light(s)");
       else st.selected_light = n;
       return ScriptStep::done;
     }},
    {"light-size", "W H", 2, 2, true, check_positive,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       int l = target_light(r, st, c);
       if (l >= 0 && st.apply(LightShapeEdit{l, {}, vec2(num(c, 0), num(c, 1)), {}}) == Tier::none)
         fail(r, c, "light-size: light " + std::to_string(l) + " has no W x H (a sphere: use light-scale)");
       return ScriptStep::done;
     }},
    {"light-scale", "S", 1, 1, true, check_positive,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       int l = target_light(r, st, c);
       if (l >= 0) st.apply(LightShapeEdit{l, {}, {}, num(c, 0)});
       return ScriptStep::done;
     }},
    {"light-position", "X Y Z", 3, 3, true, check_none,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       int l = target_light(r, st, c);
       if (l >= 0) st.apply(LightShapeEdit{l, vec3(num(c, 0), num(c, 1), num(c, 2)), {}, {}});
       return ScriptStep::done;
     }},
    {"light-intensity", "S", 1, 1, true, check_none,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       int l = target_light(r, st, c);
       if (l < 0) return ScriptStep::done;
       vec3 e = st.scene.materials[st.lights[size_t(l)].material].emission;
       float i = max_component(e);
       st.apply(LightEmissionEdit{l, i > 0 ? e / i : vec3(1.0f), i * num(c, 0)});
       return ScriptStep::done;
     }},
    {"exposure", "STOPS", 1, 1, true, check_none,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       DisplaySettings d = st.display;
       d.exposure = num(c, 0);
       st.apply(DisplayEdit{d});
       return ScriptStep::done;
     }},
    {"tonemap", "clamp|reinhard|aces", 1, 1, false, check_tonemap,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       DisplaySettings d = st.display;
       d.tonemap = *value_of<Tonemap>(kTonemapNames, c.args[0]);
       st.apply(DisplayEdit{d});
       return ScriptStep::done;
     }},
    {"display", "image|error|samples|reference-error", 1, 1, false, check_display_mode,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       const DisplayMode mode = *value_of<DisplayMode>(kDisplayModeNames, c.args[0]);
       if (st.display_mode != mode && st.apply(DisplayModeEdit{mode}) == Tier::none) {
         fail(r, c, "display reference-error: needs --reference");
         return ScriptStep::done;
       }
       // Done once the mode can be shown: a full frame of the current epoch, with its map for error / samples
       // (republished at once by the session), so a following screenshot shows the mode.
       const SessionFrame& f = st.frame;
       bool ready = mode == DisplayMode::image ||
                    (st.session && f.epoch == st.session->epoch() && !f.preview && f.frames > 0 &&
                     (mode == DisplayMode::error     ? f.rel_error.width == f.width
                      : mode == DisplayMode::samples ? f.spp_map.width == f.width
                                                     : true));
       return ready ? ScriptStep::done : ScriptStep::wait;
     }},
    {"noise-threshold", "T [MIN_SPP]", 1, 2, true, check_noise_threshold,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       AdaptiveParams a;
       a.noise_threshold = std::strtod(c.args[0].c_str(), nullptr);
       a.min_spp = c.args.size() > 1 ? whole(c, 1) : 0;
       st.apply(AdaptiveEdit{a});  // no restart: stopped pixels resume when the threshold drops
       return ScriptStep::done;
     }},
    {"compare", "off | [integrator=I] [light-sampling=L] [sampler=S] [adaptive=T|off]", 1, 4, false, check_compare,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       st.apply(CompareEdit{std::get<std::optional<CompareConfig>>(parse_compare(c.args, st.params))});
       return ScriptStep::done;
     }},
    {"divider", "F", 1, 1, true, check_fraction,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       st.apply(DividerEdit{num(c, 0)});
       return ScriptStep::done;
     }},
    {"window", "W H", 2, 2, true, check_window_size, run_window},
    {"load", "PATH", 1, 1, false, check_none,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       st.start_load(c.args[0]);
       return ScriptStep::done;
     }},
    {"wait-frames", "N", 1, 1, true, check_count,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       const int n = whole(c, 0);
       bool ready = !st.loading.valid() && st.session && st.frame.epoch == st.session->epoch() && st.frame.frames >= n;
       if (st.compare && st.session_b)  // in a compare, both sides
         ready = ready && st.frame_b.epoch == st.session_b->epoch() && st.frame_b.frames >= n;
       return ready ? ScriptStep::done : ScriptStep::wait;
     }},
    {"wait-spp", "N", 1, 1, true, check_count,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {  // all ranks' samples under mpirun (view/offload.h)
       bool ready = !st.loading.valid() && st.session && st.frame.epoch == st.session->epoch() && !st.frame.preview &&
                    st.frame.spp >= whole(c, 0);
       return ready ? ScriptStep::done : ScriptStep::wait;
     }},
    {"wait-ms", "N", 1, 1, true, check_count,
     [](ScriptRun& r, ViewerState&, const ScriptCommand& c) {
       auto now = std::chrono::steady_clock::now();
       if (!r.deadline) r.deadline = now + std::chrono::milliseconds(whole(c, 0));
       if (now < *r.deadline) return ScriptStep::wait;
       r.deadline.reset();
       return ScriptStep::done;
     }},
    {"screenshot", "PATH", 1, 1, false, check_none,
     [](ScriptRun& r, ViewerState&, const ScriptCommand& c) {
       r.screenshot_request = c.args[0];
       return ScriptStep::end_frame;  // taken at the end of this UI frame
     }},
    {"stop-at-spp", "N", 1, 1, true, check_count,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       st.apply(StopEdit{whole(c, 0)});  // as the Render panel's "stop at spp"; 0: never stop
       return ScriptStep::done;
     }},
    {"pause", "on | off", 1, 1, false, check_on_off,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       st.set_paused(c.args[0] == "on");  // as the Render panel's "pause" (every rank under mpirun)
       return ScriptStep::done;
     }},
    {"save", "PATH", 1, 1, false, check_none,
     [](ScriptRun&, ViewerState& st, const ScriptCommand& c) {
       st.save_current(c.args[0]);
       return ScriptStep::done;
     }},
    {"save-scene", "PATH", 1, 1, false, check_none,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       if (auto err = st.save_scene(c.args[0])) fail(r, c, "save-scene: " + err->message);
       return ScriptStep::done;
     }},
    {"expect-restart", "", 0, 0, false, check_none,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       if (st.session->epoch() == r.epoch_before_previous) fail(r, c, "expected a restart, the epoch did not change");
       return ScriptStep::done;
     }},
    {"expect-no-restart", "", 0, 0, false, check_none,
     [](ScriptRun& r, ViewerState& st, const ScriptCommand& c) {
       if (st.session->epoch() != r.epoch_before_previous) fail(r, c, "expected no restart, but the epoch changed");
       return ScriptStep::done;
     }},
    {"quit", "", 0, 0, false, check_none,
     [](ScriptRun& r, ViewerState&, const ScriptCommand&) {
       r.quit = true;
       return ScriptStep::done;
     }},
};

const ScriptCommandSpec* find_command(const std::string& name) {
  for (const ScriptCommandSpec& s : kCommands)
    if (name == s.name) return &s;
  return nullptr;
}

bool is_wait(const std::string& name) { return name == "wait-frames" || name == "wait-spp" || name == "wait-ms"; }

}  // namespace

std::span<const ScriptCommandSpec> script_commands() { return kCommands; }

Result<std::vector<ScriptCommand>> parse_script(std::string_view text, const std::string& file) {
  std::vector<ScriptCommand> out;
  std::istringstream in{std::string(text)};
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    ScriptCommand c;
    c.line = n;
    if (!(words >> c.name)) continue;
    for (std::string w; words >> w;) c.args.push_back(w);
    auto fail_at = [&](const std::string& why) { return Error{file + ":" + std::to_string(n) + ": " + why}; };
    const ScriptCommandSpec* s = find_command(c.name);
    if (!s) return fail_at("unknown command '" + c.name + "'");
    if (c.args.size() < s->min_args || c.args.size() > s->max_args)
      return fail_at("'" + c.name + "' takes " + std::to_string(s->min_args) +
                     (s->max_args != s->min_args ? " to " + std::to_string(s->max_args) : "") + " argument(s)" +
                     (*s->usage ? std::string(": ") + s->name + " " + s->usage : ""));
    if (s->numeric)
      for (const std::string& a : c.args)
        if (!is_number(a)) return fail_at("'" + c.name + "': '" + a + "' is not a number");
    if (std::string why = s->check(c.args); !why.empty()) return fail_at("'" + c.name + "': " + why);
    out.push_back(std::move(c));
  }
  return out;
}

Result<std::vector<ScriptCommand>> load_script(const std::string& path) {
  // A script is a few lines; the cap keeps a wrong path (a disk image, say) from filling memory.
  Result<std::string> text = read_whole_file(path, uint64_t(1) << 30);
  if (!text) return Error{text.error()};
  return parse_script(*text, path);
}

void ScriptRun::step(ViewerState& st) {
  screenshot_request.clear();
  window_request.reset();
  while (!done()) {
    const ScriptCommand& c = commands[next];
    const ScriptCommandSpec& spec = *find_command(c.name);
    if (!is_wait(c.name) && started != next) {
      started = next;
      epoch_before_previous = epoch_before_current;
      epoch_before_current = st.session ? st.session->epoch() : 0;
    }
    ScriptStep s = spec.run(*this, st, c);
    if (s == ScriptStep::wait) return;
    if (is_wait(c.name)) {
      epoch_before_previous = epoch_before_current;
      epoch_before_current = st.session ? st.session->epoch() : 0;
    }
    ++next;
    if (s == ScriptStep::end_frame) return;
  }
}

}  // namespace pt
