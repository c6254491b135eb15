#include "scene/json_locate.h"

#include <charconv>
#include <optional>
#include <tuple>

namespace pt {

namespace {

/// Appends the UTF-8 encoding of code point `cp`.
void append_utf8(std::string& out, uint32_t cp) {
  if (cp < 0x80) {
    out += char(cp);
  } else if (cp < 0x800) {
    out += char(0xC0 | (cp >> 6));
    out += char(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += char(0xE0 | (cp >> 12));
    out += char(0x80 | ((cp >> 6) & 0x3F));
    out += char(0x80 | (cp & 0x3F));
  } else {
    out += char(0xF0 | (cp >> 18));
    out += char(0x80 | ((cp >> 12) & 0x3F));
    out += char(0x80 | ((cp >> 6) & 0x3F));
    out += char(0x80 | (cp & 0x3F));
  }
}

/// A cursor over JSON text that counts lines as it goes.
struct Cursor {
  std::string_view t;
  size_t i = 0;
  int line = 1;

  bool done() const { return i >= t.size(); }
  char peek() const { return t[i]; }
  void skip_ws() {
    for (; !done(); ++i) {
      char c = t[i];
      if (c == '\n') ++line;
      else if (c != ' ' && c != '\t' && c != '\r') break;
    }
  }
  /// At a '"': moves past the string and returns it decoded (escapes resolved, as a parser would give the key).
  std::string string() {
    std::string s;
    ++i;
    while (!done() && t[i] != '"') {
      if (t[i] != '\\') {
        if (t[i] == '\n') ++line;  // invalid JSON, but keep the count right
        s += t[i++];
        continue;
      }
      if (++i >= t.size()) break;
      char e = t[i++];
      switch (e) {
        case 'b': s += '\b'; break;
        case 'f': s += '\f'; break;
        case 'n': s += '\n'; break;
        case 'r': s += '\r'; break;
        case 't': s += '\t'; break;
        case 'u': {
          uint32_t cp = hex4();
          if (cp >= 0xD800 && cp < 0xDC00 && i + 1 < t.size() && t[i] == '\\' && t[i + 1] == 'u') {
            i += 2;
            uint32_t low = hex4();
            cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
          }
          append_utf8(s, cp);
          break;
        }
        default: s += e;  // \" \\ \/
      }
    }
    ++i;  // the closing quote
    return s;
  }
  uint32_t hex4() {
    uint32_t v = 0;
    size_t end = std::min(i + 4, t.size());
    std::from_chars(t.data() + i, t.data() + end, v, 16);
    i = end;
    return v;
  }
  /// Moves past one value (of any depth, without recursion).
  void skip_value() {
    int depth = 0;
    do {
      skip_ws();
      if (done()) return;
      char c = t[i];
      if (c == '"') {
        string();
      } else if (c == '{' || c == '[') {
        ++depth;
        ++i;
      } else if (c == '}' || c == ']') {
        --depth;
        ++i;
      } else if (c == ',' || c == ':') {
        ++i;
      } else {  // number, true, false, null
        while (!done() && std::string_view(",:{}[] \t\r\n\"").find(t[i]) == std::string_view::npos) ++i;
      }
    } while (depth > 0);
  }
  /// At an object: moves to the value of `key` and returns true, or returns false. A key given twice is found at its
  /// last occurrence: the parser keeps the last value (nlohmann's object insertion overwrites), so that is the one a
  /// message is about.
  bool enter_key(const std::string& key) {
    skip_ws();
    if (done() || peek() != '{') return false;
    ++i;
    std::optional<std::pair<size_t, int>> found;  // (position, line) of the last match's value
    for (;;) {
      skip_ws();
      if (done() || peek() == '}') break;
      if (peek() == ',') {
        ++i;
        continue;
      }
      if (peek() != '"') break;
      bool match = string() == key;
      skip_ws();
      if (done() || peek() != ':') break;
      ++i;
      skip_ws();
      if (match) found = std::pair{i, line};
      skip_value();
    }
    if (found) std::tie(i, line) = *found;
    return found.has_value();
  }
  /// At an array: moves to element `index` and returns true, or returns false.
  bool enter_index(size_t index) {
    skip_ws();
    if (done() || peek() != '[') return false;
    ++i;
    for (size_t n = 0;; ++n) {
      skip_ws();
      if (done() || peek() == ']') return false;
      if (n == index) return true;
      skip_value();
      skip_ws();
      if (done() || peek() != ',') return false;
      ++i;
    }
  }
};

}  // namespace

int json_line_of(std::string_view text, const std::vector<std::string>& path) {
  Cursor c{text};
  if (text.starts_with("\xEF\xBB\xBF")) c.i = 3;
  c.skip_ws();
  int best = c.line;
  for (const std::string& part : path) {
    if (c.done()) break;
    bool found = false;
    size_t index = 0;
    auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), index);
    if (c.peek() == '[' && ec == std::errc() && end == part.data() + part.size()) found = c.enter_index(index);
    else if (c.peek() == '{') found = c.enter_key(part);
    if (!found) break;
    best = c.line;
  }
  return best;
}

int json_line_of_token(std::string_view text, std::string_view token) {
  if (token.empty()) return 0;
  Cursor c{text};
  while (!c.done()) {
    char ch = c.peek();
    if (ch == '"') {
      c.string();
    } else if (text.substr(c.i).starts_with(token)) {
      return c.line;
    } else {
      if (ch == '\n') ++c.line;
      ++c.i;
    }
  }
  return 0;
}

}  // namespace pt
