#include "view/viewer.h"

#include <cstdio>

namespace pt {

int run_viewer(const RenderParams&, const DisplaySettings&, const ViewerHooks&, Scene) {
  std::fprintf(stderr, "ptview: error: the viewer is not built yet; render headless with --frames N\n");
  return 2;
}

}  // namespace pt
