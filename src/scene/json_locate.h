#pragma once
/// Finds where a value sits in JSON text, so that semantic errors found after parsing (an unknown material, a
/// negative radius, ...) can still say "file:line": nlohmann::json keeps no source positions. This is a small
/// scanner, not a parser: it assumes text a JSON parser has accepted, and degrades to the nearest ancestor's line
/// on anything else.
#include <string>
#include <string_view>
#include <vector>

namespace pt {

/// `path` is a list of object keys (decoded, as a parser returns them) and array indices (decimal strings), e.g.
/// {"shapes", "2", "material"}. Returns the 1-based line where the value at the end of that path starts; when part
/// of the path does not exist, the line of the deepest value that does (the root's line for an empty path). Skips
/// a UTF-8 byte order mark; iterative, so any nesting depth is fine.
int json_line_of(std::string_view text, const std::vector<std::string>& path);

/// The line of the first occurrence of `token` outside JSON strings, or 0. For errors nlohmann reports without a
/// position (a number literal too large for a double: "number overflow parsing '1e999'").
int json_line_of_token(std::string_view text, std::string_view token);

}  // namespace pt
