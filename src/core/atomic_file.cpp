#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace pt {

std::string make_temp_path(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

std::optional<Error> write_atomically(const std::string& path,
                                      const std::function<std::string(const std::string& temp_path)>& write) {
  std::string temp = make_temp_path(path);
  std::string reason;
  try {
    reason = write(temp);
  } catch (const std::exception& e) {
    reason = e.what();
  } catch (...) {
    reason = "unknown error while writing";
  }
  if (reason.empty() && std::rename(temp.c_str(), path.c_str()) != 0) {
    reason = std::string("cannot rename into place: ") + std::strerror(errno);
  }
  if (!reason.empty()) {
    std::remove(temp.c_str());
    return Error{path + ": " + reason};
  }
  return std::nullopt;
}

std::optional<Error> write_file_atomic(const std::string& path, std::string_view bytes) {
  return write_atomically(path, [&](const std::string& temp) -> std::string {
    FILE* f = std::fopen(temp.c_str(), "wb");
    if (!f) return std::string("cannot open for writing: ") + std::strerror(errno);
    size_t written = std::fwrite(bytes.data(), 1, bytes.size(), f);
    bool ok = written == bytes.size();
    int err = errno;
    if (std::fclose(f) != 0 && ok) {
      ok = false;
      err = errno;
    }
    if (!ok) return std::string("write failed: ") + std::strerror(err);
    return {};
  });
}

}  // namespace pt
