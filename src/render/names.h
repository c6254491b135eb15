#pragma once
/// The names of the render enums, used everywhere they are spelled: command line, panels, script, stats JSON.
/// The material type's table lives with MaterialType (scene/scene.h), since the loaders need it.
#include "core/name_table.h"
#include "render/image.h"
#include "render/render_params.h"

namespace pt {

inline constexpr EnumName<IntegratorKind> kIntegratorNames[] = {
    {IntegratorKind::automatic, "auto"}, {IntegratorKind::mis, "mis"}, {IntegratorKind::nee, "nee"},
    {IntegratorKind::bsdf, "bsdf"}};
inline constexpr EnumName<LightSampling> kLightSamplingNames[] = {
    {LightSampling::automatic, "auto"}, {LightSampling::solid_angle, "solid-angle"}, {LightSampling::area, "area"}};
inline constexpr EnumName<SamplerKind> kSamplerNames[] = {
    {SamplerKind::sobol, "sobol"}, {SamplerKind::independent, "independent"}};
inline constexpr EnumName<Tonemap> kTonemapNames[] = {
    {Tonemap::clamp, "clamp"}, {Tonemap::reinhard, "reinhard"}, {Tonemap::aces, "aces"}};

inline const char* name_of(IntegratorKind v) { return name_of<IntegratorKind>(kIntegratorNames, v); }
inline const char* name_of(LightSampling v) { return name_of<LightSampling>(kLightSamplingNames, v); }
inline const char* name_of(SamplerKind v) { return name_of<SamplerKind>(kSamplerNames, v); }
inline const char* name_of(Tonemap v) { return name_of<Tonemap>(kTonemapNames, v); }

}  // namespace pt
