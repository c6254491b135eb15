#include "view/script.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace pt {

namespace {

bool is_number(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v);
}

}  // namespace

Result<std::vector<ScriptCommand>> load_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open script"};
  // name -> (min args, max args, all numeric)
  struct Spec { size_t min, max; bool numeric; };
  const std::map<std::string, Spec> specs = {
      {"orbit", {2, 2, true}},         {"pan", {2, 2, true}},          {"dolly", {1, 1, true}},
      {"pick", {2, 2, true}},          {"set-material", {1, 4, false}}, {"light-size", {2, 2, true}},
      {"light-intensity", {1, 1, true}}, {"exposure", {1, 1, true}},   {"tonemap", {1, 1, false}},
      {"load", {1, 1, false}},         {"wait-frames", {1, 1, true}},  {"wait-ms", {1, 1, true}},
      {"screenshot", {1, 1, false}},   {"save", {1, 1, false}},        {"expect-restart", {0, 0, false}},
      {"expect-no-restart", {0, 0, false}}, {"quit", {0, 0, false}},
  };
  std::vector<ScriptCommand> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    ScriptCommand c;
    c.line = n;
    if (!(words >> c.name)) continue;
    for (std::string w; words >> w;) c.args.push_back(w);
    auto fail = [&](const std::string& why) { return Error{path + ":" + std::to_string(n) + ": " + why}; };
    auto it = specs.find(c.name);
    if (it == specs.end()) return fail("unknown command '" + c.name + "'");
    const Spec& s = it->second;
    if (c.args.size() < s.min || c.args.size() > s.max)
      return fail("'" + c.name + "' takes " + std::to_string(s.min) +
                  (s.max != s.min ? " to " + std::to_string(s.max) : "") + " argument(s)");
    if (s.numeric)
      for (const std::string& a : c.args)
        if (!is_number(a)) return fail("'" + c.name + "': '" + a + "' is not a number");
    if (c.name == "set-material") {
      const std::string& type = c.args[0];
      if (type != "diffuse" && type != "specular" && type != "glass") return fail("unknown material type '" + type + "'");
      for (size_t k = 1; k < c.args.size(); ++k) {
        const std::string& kv = c.args[k];
        size_t eq = kv.find('=');
        std::string key = kv.substr(0, eq);
        if (eq == std::string::npos || (key != "albedo" && key != "ior" && key != "emission"))
          return fail("expected albedo=r,g,b, ior=x or emission=r,g,b, got '" + kv + "'");
        std::stringstream vals(kv.substr(eq + 1));
        int count = 0;
        for (std::string v; std::getline(vals, v, ',');) {
          if (!is_number(v)) return fail("'" + kv + "': '" + v + "' is not a number");
          ++count;
        }
        if (count != (key == "ior" ? 1 : 3)) return fail("'" + kv + "': wrong number of values");
      }
    }
    if (c.name == "tonemap" && c.args[0] != "clamp" && c.args[0] != "reinhard" && c.args[0] != "aces")
      return fail("unknown tonemap '" + c.args[0] + "'");
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace pt
