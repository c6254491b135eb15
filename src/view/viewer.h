#pragma once
/// The interactive window: GLFW + OpenGL 3.3 core (glad loader) + Dear ImGui, driving the progressive renderer.
#include "render/image.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "view/offload.h"
#include "view/viewer_hooks.h"

namespace pt {

/// Opens the window on `scene` and runs until closed; returns the exit code (2 without a display). With `offload`
/// (rank 0 under mpirun) the other ranks render too.
int run_viewer(const RenderParams& params, const DisplaySettings& display, const ViewerHooks& hooks, Scene scene,
               OffloadRoot* offload = nullptr);

}  // namespace pt
