#pragma once
/// Result<T>: a value or an error message. Loaders and parsers return this instead of throwing through the renderer.
#include <optional>
#include <string>
#include <utility>

namespace pt {

/// An error message already formatted for the user, "file:line: reason" where a location is known. Always one
/// line: control characters that came in through file names, JSON keys or file contents are escaped, and very long
/// messages are cut, so a user (or a script) always reads exactly one line.
struct Error {
  std::string message;

  Error() = default;
  Error(std::string text) : message(one_line(std::move(text))) {}  // NOLINT: implicit from a string

  static std::string one_line(std::string text) {
    static const char* hex = "0123456789abcdef";
    std::string out;
    out.reserve(text.size());
    for (char ch : text) {
      unsigned char c = static_cast<unsigned char>(ch);
      if (c == '\n') out += "\\n";
      else if (c == '\r') out += "\\r";
      else if (c == '\t') out += "\\t";
      else if (c < 0x20 || c == 0x7f) out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
      else out += ch;
      if (out.size() > 4000) {
        out += "...";
        break;
      }
    }
    return out;
  }
};

template <class T>
class Result {
 public:
  Result(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design, like std::expected
  Result(Error error) : error_(std::move(error.message)) {}  // NOLINT
  bool ok() const { return value_.has_value(); }
  explicit operator bool() const { return ok(); }
  T& value() { return *value_; }
  const T& value() const { return *value_; }
  T& operator*() { return *value_; }
  const T& operator*() const { return *value_; }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }
  const std::string& error() const { return error_; }

 private:
  std::optional<T> value_;
  std::string error_;
};

}  // namespace pt
