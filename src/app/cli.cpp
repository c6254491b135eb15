/// The command line, parsed with CLI11; every malformed value becomes one error line and exit code 2.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <filesystem>

#include "app/options.h"
#include "core/file_name.h"
#include "render/names.h"

namespace pt {

namespace {

/// "WxH" with both in [1, 16384].
bool parse_size(const std::string& s, int& w, int& h) {
  size_t x = s.find_first_of("xX");
  if (x == std::string::npos) return false;
  auto parse = [](std::string_view v, int& out) {
    if (v.empty()) return false;
    auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
    return ec == std::errc() && ptr == v.data() + v.size() && out >= 1 && out <= 16384;
  };
  return parse(std::string_view(s).substr(0, x), w) && parse(std::string_view(s).substr(x + 1), h);
}

std::string check_output_dir(const std::string& option, const std::string& path) {
  std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) parent = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(parent, ec))
    return option + (std::filesystem::exists(parent, ec) ? ": not a directory: " : ": directory does not exist: ") +
           parent.string();
  if (::access(parent.c_str(), W_OK) != 0) return option + ": directory is not writable: " + parent.string();
  if (std::filesystem::is_directory(path, ec)) return option + ": is a directory: " + path;
  return {};
}

}  // namespace

ParseOutcome parse_command_line(int argc, const char* const* argv) {
  AppOptions o;
  CLI::App app{"ptview: an interactive progressive path tracer. Without --frames it opens a window."};
  app.set_version_flag("--version", "ptview 0.1");
  // A repeated option takes its last value, so scripts can append overrides.
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  // Defaults come from RenderParams and the name tables: one place for each.
  std::string size = "512x512", integrator = name_of(o.render.integrator),
              light_sampling = name_of(o.render.light_sampling), sampler = name_of(o.render.sampler);
  int frames = 0;
  double time_limit = 0;
  std::string seed = "0";
  app.add_option("scene", o.scene_path,
                 "Scene file: .obj (materials from its .mtl), .json, .gltf or .glb; omitted: built-in scene");
  auto* frames_opt = app.add_option("--frames", frames, "Headless: render N progressive frames, write --out, exit");
  app.add_option("--spp-per-frame", o.render.spp_per_frame, "Samples per pixel added each frame (default 1)");
  auto* size_opt = app.add_option("--size", size, "Image size WxH (default 512x512; the viewer follows the window)");
  app.add_option("--seed", seed, "Random seed (default 0)");
  app.add_option("--threads", o.render.threads, "Worker threads (default: all cores)");
  auto* out_opt = app.add_option("--out", o.out, "Output image: .png (tonemapped sRGB), .pfm or .exr (linear mean)");
  app.add_option("--max-depth", o.render.max_depth, "Maximum path depth, pbrt convention (default 64)");
  app.add_option("--integrator", integrator, "auto (default: nee; mis with --light-sampling area), mis, nee or bsdf");
  app.add_option("--light-sampling", light_sampling,
                 "auto (default: solid angle where it pays, per scene and point), solid-angle or area");
  app.add_option("--sampler", sampler, "sobol (default: Owen-scrambled Sobol) or independent");
  app.add_option("--stats-json", o.stats_json, "Write run statistics as JSON");
  app.add_option("--reference", o.reference,
                 "Reference image (.pfm/.exr) for --error-csv; viewer: true relMSE and the reference-error display");
  app.add_option("--error-csv", o.error_csv, "After every frame append frame,spp,seconds,rmse,rel_mse,est_rel_mse");
  app.add_option("--error-map", o.error_map, "Headless: write the per-pixel relative standard error (.pfm/.exr)");
  app.add_option("--spp-map", o.spp_map, "Headless: write the samples each pixel received (.pfm/.exr)");
  auto* threshold_opt = app.add_option("--noise-threshold", o.adaptive.noise_threshold,
                                       "Adaptive sampling: pixels whose relative standard error is below T stop");
  auto* min_spp_opt = app.add_option("--min-spp", o.adaptive.min_spp,
                                     "Adaptive sampling: samples before the first check (default ceil(16/T^0.3))");
  int max_spp = 0;
  auto* max_spp_opt = app.add_option("--max-spp", max_spp, "Headless: stop at N samples per pixel");
  auto* time_opt = app.add_option("--time-limit", time_limit, "Headless: stop after S seconds");
  app.add_option("--exposure", o.display.exposure, "Display exposure in stops (PNG output and viewer)");
  std::string tonemap = "clamp";
  app.add_option("--tonemap", tonemap, "clamp (default), reinhard or aces (PNG output and viewer)");
  int quit_after = 0;
  auto* quit_opt = app.add_option("--quit-after-frames", quit_after, "Viewer: quit after N rendered frames");
  app.add_option("--screenshot", o.viewer.screenshot, "Viewer: save a PNG of the window at exit");
  app.add_option("--script", o.viewer.script, "Viewer: run scripted input from FILE");
  app.add_option("--camera", o.camera, "Use camera N of the scene file (glTF cameras in node order, from 0)")
      ->check(CLI::Range(0, 1 << 20));

  ParseOutcome result;
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    result.message = app.help();
    return result;
  } catch (const CLI::CallForVersion&) {
    result.message = "ptview 0.1\n";
    return result;
  } catch (const CLI::ParseError& e) {
    result.exit_code = 2;
    result.message = e.what();
    return result;
  }
  auto fail = [&](std::string msg) {
    result.exit_code = 2;
    result.message = std::move(msg);
    return result;
  };
  if (!parse_size(size, o.render.width, o.render.height))
    return fail("--size: expected WxH with W and H from 1 to 16384, got '" + size + "'");
  if (int64_t(o.render.width) * o.render.height > (int64_t(1) << 26))
    return fail("--size: " + size + " is more than 67108864 pixels (the film would not fit in memory)");
  if (frames_opt->count()) {
    if (frames < 1) return fail("--frames: must be at least 1, got " + std::to_string(frames));
    o.frames = frames;
  }
  if (o.render.spp_per_frame < 1 || o.render.spp_per_frame > 1 << 20)
    return fail("--spp-per-frame: must be from 1 to 1048576");
  {
    auto [ptr, ec] = std::from_chars(seed.data(), seed.data() + seed.size(), o.render.seed);
    if (seed.empty() || ec != std::errc() || ptr != seed.data() + seed.size())
      return fail("--seed: expected an integer from 0 to 18446744073709551615, got '" + seed + "'");
  }
  if (o.render.threads < 0 || o.render.threads > 1024) return fail("--threads: must be from 0 (all cores) to 1024");
  if (o.render.max_depth < 0 || o.render.max_depth > 1000000) return fail("--max-depth: must be from 0 to 1000000");
  // One name table per enum (render/names.h); "none" is an old alias of clamp.
  auto pick = []<class E, size_t N>(const EnumName<E> (&table)[N], const std::string& option,
                                    const std::string& value, E& out) {
    std::optional<E> v = value_of<E>(table, value);
    if (!v) return option + ": expected " + names_list<E>(table) + ", got '" + value + "'";
    out = *v;
    return std::string();
  };
  if (tonemap == "none") tonemap = "clamp";
  for (const std::string& err :
       {pick(kIntegratorNames, "--integrator", integrator, o.render.integrator),
        pick(kLightSamplingNames, "--light-sampling", light_sampling, o.render.light_sampling),
        pick(kSamplerNames, "--sampler", sampler, o.render.sampler),
        pick(kTonemapNames, "--tonemap", tonemap, o.display.tonemap)})
    if (!err.empty()) return fail(err);
  if (!std::isfinite(o.display.exposure) || std::abs(o.display.exposure) > 64)
    return fail("--exposure: must be a finite number of stops from -64 to 64");
  if (time_opt->count()) {
    if (!(time_limit > 0) || !std::isfinite(time_limit))
      return fail("--time-limit: must be a positive number of seconds");
    o.time_limit = time_limit;
  }
  if (threshold_opt->count()) {
    const double t = o.adaptive.noise_threshold;
    if (!std::isfinite(t) || !(t > 0.0) || t > 1.0)
      return fail("--noise-threshold: must be a relative error greater than 0 and at most 1");
  }
  if (min_spp_opt->count()) {
    if (!threshold_opt->count()) return fail("--min-spp: needs --noise-threshold");
    if (o.adaptive.min_spp < 1 || o.adaptive.min_spp > (1 << 24)) return fail("--min-spp: must be from 1 to 16777216");
  }
  if (max_spp_opt->count()) {
    if (max_spp < 1 || max_spp > (1 << 30)) return fail("--max-spp: must be from 1 to 1073741824");
    o.max_spp = max_spp;
  }
  for (auto [name, path] : {std::pair{"--error-map", &o.error_map}, std::pair{"--spp-map", &o.spp_map}}) {
    if (path->empty()) continue;
    if (!o.headless()) return fail(std::string(name) + ": headless only (with --frames, --time-limit or --max-spp)");
    if (!is_float_image_extension(*path)) return fail(std::string(name) + ": must be a .pfm or .exr file: " + *path);
    if (std::string err = check_output_dir(name, *path); !err.empty()) return fail(err);
  }
  if (quit_opt->count()) {
    if (quit_after < 1) return fail("--quit-after-frames: must be at least 1");
    o.viewer.quit_after_frames = quit_after;
  }
  o.out_given = out_opt->count() > 0;
  if (!o.out_given) o.out = "ptview.png";
  if (!is_supported_image_extension(o.out))
    return fail("--out: unsupported image type '" + o.out + "' (use .png, .pfm or .exr)");
  if (o.out_given) {
    if (std::string err = check_output_dir("--out", o.out); !err.empty()) return fail(err);
  }
  if (!o.viewer.screenshot.empty()) {
    if (lower_extension(o.viewer.screenshot) != ".png") return fail("--screenshot: must be a .png file");
    if (std::string err = check_output_dir("--screenshot", o.viewer.screenshot); !err.empty()) return fail(err);
  }
  if (!o.stats_json.empty())
    if (std::string err = check_output_dir("--stats-json", o.stats_json); !err.empty()) return fail(err);
  if (!o.error_csv.empty()) {
    if (std::string err = check_output_dir("--error-csv", o.error_csv); !err.empty()) return fail(err);
  }
  if (!o.reference.empty() && !is_float_image_extension(o.reference))
    return fail("--reference: must be a .pfm or .exr file: " + o.reference);
  o.viewer.stats_json = o.stats_json;
  o.viewer.lock_size = size_opt->count() > 0;
  o.viewer.reference = o.reference;
  o.viewer.adaptive = o.adaptive;
  if (o.out_given) o.viewer.out = o.out;
  result.options = std::move(o);
  return result;
}

}  // namespace pt
