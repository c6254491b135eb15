#pragma once
/// Atomic file replacement: write everything to a temporary file in the target's directory, then rename it over the
/// target. A failure or crash midway never leaves a partial file under the target's name.
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "core/result.h"

namespace pt {

/// A temporary path next to `path` ("<path>.tmp.<pid>.<n>"), unique within this process.
std::string make_temp_path(const std::string& path);

/// Calls `write(temp_path)`, which creates and fills the temporary file and returns an error message on failure
/// (empty on success); on success renames it to `path`. On any failure the temporary file is removed and the error
/// is returned as "PATH: reason".
std::optional<Error> write_atomically(const std::string& path,
                                      const std::function<std::string(const std::string& temp_path)>& write);

/// write_atomically for a byte string.
std::optional<Error> write_file_atomic(const std::string& path, std::string_view bytes);

}  // namespace pt
