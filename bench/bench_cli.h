#pragma once
/// The benchmark programs' command lines, parsed by CLI11 as ptview's own (src/app/cli.cpp): `--help` lists the
/// options, and a mistyped option, a missing or malformed value or an unknown name is one line on stderr and exit 2,
/// where a hand-rolled loop ignored it and ran for twenty minutes with the defaults.
#include <CLI/CLI.hpp>

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

/// The names of a comma-separated list that are not among `known` ("" when all are).
inline std::string unknown_names(const std::string& list, const std::vector<std::string>& known) {
  std::string unknown;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    bool found = false;
    for (const std::string& k : known) found = found || k == name;
    if (!found && !name.empty()) unknown += (unknown.empty() ? "" : ", ") + name;
  }
  return unknown;
}

}  // namespace bench
