#include "core/read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <new>

namespace pt {

namespace {

/// Closes the descriptor on every return path.
struct FileDescriptor {
  int fd;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

/// "2 GiB" for a whole number of GiB, else the bytes.
std::string size_text(uint64_t bytes) {
  constexpr uint64_t kGiB = uint64_t(1) << 30;
  if (bytes >= kGiB && bytes % kGiB == 0) return std::to_string(bytes / kGiB) + " GiB";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

Result<std::string> read_whole_file(const std::string& path, uint64_t max_bytes) {
  // O_NONBLOCK changes nothing for a regular file; it only keeps the open of a FIFO from waiting.
  const FileDescriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
  if (file.fd < 0) return Error{path + ": cannot open: " + std::strerror(errno)};
  struct stat st {};
  if (::fstat(file.fd, &st) != 0) return Error{path + ": cannot open: " + std::strerror(errno)};
  if (S_ISDIR(st.st_mode)) return Error{path + ": cannot open: is a directory"};
  if (!S_ISREG(st.st_mode)) return Error{path + ": cannot open: not a regular file"};
  if (uint64_t(st.st_size) > max_bytes)
    return Error{path + ": cannot open: larger than " + size_text(max_bytes)};
  try {
    std::string bytes(size_t(st.st_size), '\0');
    size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::read(file.fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) return Error{path + ": read error: " + std::strerror(errno)};
      if (n == 0) break;  // the file shrank since fstat
      done += size_t(n);
    }
    bytes.resize(done);
    return bytes;
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  }
}

}  // namespace pt
