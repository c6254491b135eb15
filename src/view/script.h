#pragma once
/// Scripted input for the windowed mode (--script FILE): one command per line, `#` starts a comment. Every command
/// is one row of the table in script.cpp (name, arguments, check, run), and runs by producing the same Edit values
/// as the mouse, keyboard and panels. The README's command table is the only other list.
#include <array>
#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace pt {

struct ViewerState;

struct ScriptCommand {
  int line = 0;
  std::string name;
  std::vector<std::string> args;
};

/// Parses and validates a whole script up front; errors are "FILE:LINE: reason".
Result<std::vector<ScriptCommand>> parse_script(std::string_view text, const std::string& file);
Result<std::vector<ScriptCommand>> load_script(const std::string& path);

/// What the window shows, set by the viewer before each step: the `window` command waits on it.
struct WindowView {
  int window_w = 0, window_h = 0;  ///< the window's size in screen units (glfwGetWindowSize)
  int follow_w = 0, follow_h = 0;  ///< the size the render follows to: the image area's (view/input.h)
  bool size_locked = true;         ///< --size, the Render panel's lock or an empty area: the render does not follow
};

/// A script being run, one UI frame at a time.
struct ScriptRun {
  std::string file;
  std::vector<ScriptCommand> commands;
  size_t next = 0;
  uint64_t epoch_before_previous = 0, epoch_before_current = 0;
  /// The running command's deadline, set on its first step and cleared when it ends (wait-ms: the end of the
  /// wait; window: when it gives up on the window system).
  std::optional<std::chrono::steady_clock::time_point> deadline;
  size_t started = size_t(-1);  ///< index of the command whose epoch bookkeeping is done (it may wait: display)
  int failures = 0;                ///< failed expectations and impossible commands (exit code 3)
  bool quit = false;
  std::string screenshot_request;  ///< a window PNG to write at the end of this UI frame
  WindowView window;               ///< set by the viewer before each step
  std::optional<std::array<int, 2>> window_request;  ///< a window size (screen units) to set after this step

  bool done() const { return next >= commands.size(); }
  /// Runs commands until one has to wait for frames or time, or asks for a screenshot.
  void step(ViewerState& st);
};

/// What a command does when run: finished, or keep its place and try again next UI frame.
enum class ScriptStep { done, wait, end_frame };

/// One row of the command table.
struct ScriptCommandSpec {
  const char* name;
  const char* usage;  ///< arguments, as in the README
  size_t min_args, max_args;
  bool numeric;       ///< every argument must be a finite number
  /// Extra checks at parse time; returns an error reason or "".
  std::string (*check)(const std::vector<std::string>& args);
  /// Runs it; `fail` records a failure (exit code 3) with the command's line.
  ScriptStep (*run)(ScriptRun& run, ViewerState& st, const ScriptCommand& c);
};

std::span<const ScriptCommandSpec> script_commands();

}  // namespace pt
