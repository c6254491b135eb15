#pragma once
/// Entry points of the program: parse, load, then run headless or open the viewer.
#include "app/options.h"
#include "dist/cluster.h"
#include "render/image_error.h"
#include "render/render_scene.h"
#include "render/stats.h"
#include "render/stats_json.h"

namespace pt {

/// The whole program; returns the process exit code (0 ok, 2 bad input or failure).
int run_app(int argc, const char* const* argv);

/// Renders options.frames frames (or until the time limit) without a window, writes outputs; returns exit code.
/// With several ranks (src/dist), each renders its share of the frames and rank 0 writes the outputs.
/// `load_ms`: how long reading and parsing the scene took (the caller loaded it), reported as the stats' load_ms.
int run_headless(const AppOptions& options, const Scene& scene, Cluster& cluster, double load_ms = 0.0);

}  // namespace pt
