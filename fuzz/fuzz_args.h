#pragma once
// How the command-line fuzzer turns bytes into an argument vector (shared with its regression test).
#include <string>
#include <vector>

namespace pt::fuzz {

/// "ptview" followed by the input split at NUL and newline bytes.
inline std::vector<std::string> split_args(const char* data, size_t size) {
  std::vector<std::string> args = {"ptview"};
  std::string cur;
  for (size_t i = 0; i < size; ++i) {
    char c = data[i];
    if (c == '\0' || c == '\n') {
      args.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) args.push_back(cur);
  return args;
}

}  // namespace pt::fuzz
