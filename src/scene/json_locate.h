#pragma once
/// Finds the line where a value sits in JSON text, so that semantic errors found after parsing (an unknown
/// material, a negative radius, ...) can still say "file:line". nlohmann::json keeps no source positions.
#include <string>
#include <string_view>
#include <vector>

namespace pt {

/// `path` is a list of object keys and array indices (as decimal strings), e.g. {"shapes", "2", "material"}.
/// Returns the 1-based line of the deepest value on that path that exists (the root's line for an empty path).
int json_line_of(std::string_view text, const std::vector<std::string>& path);

}  // namespace pt
