#pragma once
/// Every change a user makes in the viewer, as a value. The mouse, the keyboard, the panels and the script all turn
/// their input into an Edit and hand it to ViewerState::apply, which alone decides what has to be recomputed (the
/// restart tier) and does it. To add an input, produce an existing Edit; to add a kind of change (a display mode,
/// an A/B compare), add a struct here, a case to tier_of and to ViewerState::apply.
#include <memory>
#include <optional>
#include <variant>

#include "render/adaptive.h"
#include "render/image.h"
#include "render/render_params.h"
#include "scene/scene.h"
#include "view/display_mode.h"

namespace pt {

/// What an edit costs, cheapest first.
enum class Tier : uint8_t {
  none,        ///< nothing changed (a rejected or empty edit)
  display,     ///< display transform or display mode only: no restart
  sampling,    ///< adaptive sampling or the stop: no restart (stopped pixels resume when the threshold drops)
  camera,      ///< restart over the same render scene (camera or render parameters)
  material,    ///< new materials and light list over the same geometry
  light_refit, ///< shapes moved or resized: BVH refit, then as material
  rebuild,     ///< new geometry: a full BVH build (done off the UI thread for loads)
};
inline constexpr EnumName<Tier> kTierNames[] = {{Tier::none, "none"},         {Tier::display, "display"},
                                                {Tier::sampling, "sampling"},
                                                {Tier::camera, "camera"},     {Tier::material, "material"},
                                                {Tier::light_refit, "light-refit"}, {Tier::rebuild, "rebuild"}};

struct CameraEdit {
  Camera camera;
};
struct RenderParamsEdit {
  RenderParams params;
};
struct DisplayEdit {
  DisplaySettings display;
};
/// What the image area shows (image, error, samples, reference-error); rejected (none) for reference-error without
/// a --reference.
struct DisplayModeEdit {
  DisplayMode mode = DisplayMode::image;
};
/// Adaptive sampling on (noise_threshold > 0) or off, applied to the running epoch (RenderSession::set_adaptive).
struct AdaptiveEdit {
  AdaptiveParams adaptive;
};
/// Where rendering stops: at `spp` samples per pixel on both sides of a compare (0: never), for this epoch and the
/// next ones. A stop below the samples already taken stops at once and keeps them.
struct StopEdit {
  int spp = 0;
};
/// The second configuration of an equal-time A/B compare: what differs from A (the current parameters).
struct CompareConfig {
  IntegratorKind integrator = IntegratorKind::mis;
  LightSampling light_sampling = LightSampling::automatic;
  SamplerKind sampler = SamplerKind::sobol;
  AdaptiveParams adaptive;
  bool operator==(const CompareConfig& o) const {
    return integrator == o.integrator && light_sampling == o.light_sampling && sampler == o.sampler &&
           adaptive.noise_threshold == o.adaptive.noise_threshold && adaptive.min_spp == o.adaptive.min_spp;
  }
};
/// Starts (restarting both sides) or, with no config, ends an A/B compare.
struct CompareEdit {
  std::optional<CompareConfig> b;
};
/// Where A ends and B begins, as a fraction of the image width.
struct DividerEdit {
  float x = 0.5f;
};
/// Replaces material `index`; apply normalizes it (albedo in [0,1], glass albedo 1, emission >= 0, ior >= 1).
struct MaterialEdit {
  int index = -1;
  Material material;
};
/// Changes light `light` (index into ViewerState::lights): any of a new center, a new W x H, a scale factor.
struct LightShapeEdit {
  int light = -1;
  std::optional<vec3> center;
  std::optional<vec2> size;
  std::optional<float> scale;
};
/// A light's colour (max component 1) and intensity: its material's emission = color * intensity.
struct LightEmissionEdit {
  int light = -1;
  vec3 color{1.0f};
  float intensity = 1.0f;
};
/// A scene whose geometry is already built (a finished background load).
struct LoadedScene;
struct SceneEdit {
  std::shared_ptr<LoadedScene> loaded;
};
/// Restart accumulation as is (the Render panel's button).
struct RestartEdit {};

using Edit = std::variant<CameraEdit, RenderParamsEdit, DisplayEdit, DisplayModeEdit, AdaptiveEdit, StopEdit,
                          CompareEdit, DividerEdit, MaterialEdit, LightShapeEdit, LightEmissionEdit, SceneEdit, RestartEdit>;

/// The tier an edit of this kind needs (before looking at the state: apply may still return none for an edit that
/// changes nothing or is invalid).
inline Tier tier_of(const Edit& e) {
  struct V {
    Tier operator()(const CameraEdit&) const { return Tier::camera; }
    Tier operator()(const RenderParamsEdit&) const { return Tier::camera; }
    Tier operator()(const DisplayEdit&) const { return Tier::display; }
    Tier operator()(const DisplayModeEdit&) const { return Tier::display; }
    Tier operator()(const AdaptiveEdit&) const { return Tier::sampling; }
    Tier operator()(const StopEdit&) const { return Tier::sampling; }
    Tier operator()(const CompareEdit&) const { return Tier::camera; }
    Tier operator()(const DividerEdit&) const { return Tier::display; }
    Tier operator()(const MaterialEdit&) const { return Tier::material; }
    Tier operator()(const LightShapeEdit&) const { return Tier::light_refit; }
    Tier operator()(const LightEmissionEdit&) const { return Tier::material; }
    Tier operator()(const SceneEdit&) const { return Tier::rebuild; }
    Tier operator()(const RestartEdit&) const { return Tier::camera; }
  };
  return std::visit(V{}, e);
}

}  // namespace pt
