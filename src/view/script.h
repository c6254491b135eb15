#pragma once
/// Scripted input for the windowed mode (--script FILE): one command per line, run in order through the same code
/// paths as mouse, keyboard and panels. Used by the GUI tests and for reproducible demos. Commands:
///   orbit DX DY | pan DX DY | dolly F | pick X Y | set-material TYPE [albedo=r,g,b] [ior=x] [emission=r,g,b]
///   light-size W H | light-intensity S | exposure STOPS | tonemap clamp|reinhard|aces | load PATH
///   wait-frames N | wait-ms N | screenshot PATH | save PATH | expect-restart | expect-no-restart | quit
#include <string>
#include <vector>

#include "core/result.h"

namespace pt {

struct ScriptCommand {
  int line = 0;
  std::string name;
  std::vector<std::string> args;
};

/// Parses and validates the whole file up front; errors are "FILE:LINE: reason".
Result<std::vector<ScriptCommand>> load_script(const std::string& path);

}  // namespace pt
