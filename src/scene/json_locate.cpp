#include "scene/json_locate.h"

#include <charconv>

namespace pt {

namespace {

/// A minimal, forgiving JSON walker: it only needs to skip values and match keys in text nlohmann has already
/// accepted as valid.
struct Walker {
  std::string_view t;
  size_t i = 0;
  int line = 1;

  bool done() const { return i >= t.size(); }
  void skip_ws() {
    while (!done() && (t[i] == ' ' || t[i] == '\t' || t[i] == '\r' || t[i] == '\n')) {
      if (t[i] == '\n') ++line;
      ++i;
    }
  }
  /// Reads a string starting at the quote; returns its raw contents (escapes kept, which is enough for keys).
  std::string_view string() {
    size_t start = ++i;
    while (!done() && t[i] != '"') {
      if (t[i] == '\\') ++i;
      else if (t[i] == '\n') ++line;
      ++i;
    }
    std::string_view s = t.substr(start, std::min(i, t.size()) - start);
    ++i;
    return s;
  }
  void skip_value() {
    skip_ws();
    if (done()) return;
    char c = t[i];
    if (c == '"') {
      string();
    } else if (c == '{' || c == '[') {
      char close = c == '{' ? '}' : ']';
      ++i;
      for (;;) {
        skip_ws();
        if (done()) return;
        if (t[i] == close) { ++i; return; }
        if (t[i] == ',') { ++i; continue; }
        if (close == '}') {
          if (t[i] == '"') string();
          skip_ws();
          if (!done() && t[i] == ':') ++i;
        }
        skip_value();
      }
    } else {
      while (!done() && t[i] != ',' && t[i] != '}' && t[i] != ']' && t[i] != ' ' && t[i] != '\n' && t[i] != '\t' &&
             t[i] != '\r')
        ++i;
    }
  }
  /// Positions at the value of `key` in the object starting here; false if absent.
  bool enter_key(std::string_view key) {
    skip_ws();
    if (done() || t[i] != '{') return false;
    ++i;
    for (;;) {
      skip_ws();
      if (done() || t[i] == '}') return false;
      if (t[i] == ',') { ++i; continue; }
      if (t[i] != '"') return false;
      std::string_view k = string();
      skip_ws();
      if (!done() && t[i] == ':') ++i;
      skip_ws();
      if (k == key) return true;
      skip_value();
    }
  }
  bool enter_index(size_t index) {
    skip_ws();
    if (done() || t[i] != '[') return false;
    ++i;
    size_t n = 0;
    for (;;) {
      skip_ws();
      if (done() || t[i] == ']') return false;
      if (t[i] == ',') { ++i; continue; }
      if (n == index) return true;
      skip_value();
      ++n;
    }
  }
};

}  // namespace

int json_line_of(std::string_view text, const std::vector<std::string>& path) {
  Walker w{text};
  w.skip_ws();
  int best = w.line;
  for (const std::string& part : path) {
    Walker saved = w;
    size_t index = 0;
    auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), index);
    bool is_index = ec == std::errc() && ptr == part.data() + part.size();
    w.skip_ws();
    bool found = (!w.done() && w.t[w.i] == '[' && is_index) ? w.enter_index(index) : w.enter_key(part);
    if (!found) return best;
    w.skip_ws();
    best = w.line;
    (void)saved;
  }
  return best;
}

}  // namespace pt
