#pragma once
/// The benchmark programs' command lines, parsed by CLI11 as ptview's own (src/app/cli.cpp): `--help` lists the
/// options, and a mistyped option, a missing or malformed value or an unknown name is one line on stderr and exit 2,
/// where a hand-rolled loop ignored it and ran for twenty minutes with the defaults.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace bench {

/// Parses argv; returns the exit code when the program should stop now (0 after --help, 2 on bad input).
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: %s\n", app.get_name().c_str(), e.what());
    return 2;
  }
  return std::nullopt;
}

/// Checks the comma-separated names given to `option` against `known`. Returns "" when all are known, else one line
/// naming the unknown ones and listing the known ones.
inline std::string check_names(const std::string& option, const std::string& list,
                               const std::vector<std::string>& known) {
  auto join = [](const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
  };
  std::vector<std::string> unknown;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');)
    if (!name.empty() && std::find(known.begin(), known.end(), name) == known.end()) unknown.push_back(name);
  return unknown.empty() ? "" : option + ": unknown " + join(unknown) + " (known: " + join(known) + ")";
}

}  // namespace bench
