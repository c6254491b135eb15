// libFuzzer: any argument vector must parse to options or to one error line (exit code 2), never crash.
#include <cstdint>
#include <string>
#include <vector>

#include "app/options.h"
#include "fuzz_args.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> args = pt::fuzz::split_args(reinterpret_cast<const char*>(data), size);
  if (args.size() > 64) return 0;
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  pt::ParseOutcome out = pt::parse_command_line(int(argv.size()), argv.data());
  if (!out.options && out.exit_code != 0 && out.exit_code != 2) __builtin_trap();
  return 0;
}
