// Atomic file replacement (src/core/atomic_file.h), the "never a half-written file" promise: a failure at any step
// (the writer throws, a write is cut short, the rename is refused) is one error naming the file and its reason, the
// file under the target's name is the old one, untouched, and no temporary file stays behind.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "temp_dir.h"

namespace pt {
namespace {

/// The names in `dir`, which must be `expected` alone.
void expect_only(const test::TempDir& dir, const std::string& expected) {
  std::string names;
  for (const auto& e : std::filesystem::directory_iterator(dir.path)) names += " " + e.path().filename().string();
  EXPECT_EQ(names, " " + expected) << "a temporary file stayed behind, or the file is gone";
}

TEST(AtomicFile, WritesTheBytesAndLeavesNothingElse) {
  test::TempDir dir;
  const std::string path = dir / "out.bin";
  std::string bytes(100000, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = char(i * 7 % 251);
  ASSERT_FALSE(write_file_atomic(path, "old"));
  ASSERT_FALSE(write_file_atomic(path, bytes));
  EXPECT_EQ(test::read_file(path), bytes);
  expect_only(dir, "out.bin");
}

TEST(AtomicFile, AWriterThatThrowsKeepsTheOldFile) {
  test::TempDir dir;
  const std::string path = dir.write("out.txt", "old");
  for (bool standard : {true, false}) {
    std::optional<Error> e = write_atomically(path, [&](const std::string& temp) -> std::string {
      std::ofstream(temp) << "half";
      if (standard) throw std::runtime_error("out of paper");
      throw 7;
    });
    ASSERT_TRUE(e);
    EXPECT_EQ(e->message, path + ": " + (standard ? "out of paper" : "unknown error while writing"));
    EXPECT_EQ(test::read_file(path), "old");
    expect_only(dir, "out.txt");
  }
}

/// Lowers the file-size limit for its lifetime; writes past it fail with EFBIG (SIGXFSZ ignored meanwhile).
struct FileSizeLimit {
  rlimit old{};
  void (*old_handler)(int) = nullptr;
  explicit FileSizeLimit(rlim_t bytes) {
    old_handler = std::signal(SIGXFSZ, SIG_IGN);
    getrlimit(RLIMIT_FSIZE, &old);
    rlimit lowered = old;
    lowered.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &lowered);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, old_handler);
  }
};

// A write cut short by the disk (here the file-size limit) fails, whether fwrite sees it (a write larger than
// stdio's buffer) or only the flush at fclose does (a small one).
TEST(AtomicFile, AWriteCutShortKeepsTheOldFile) {
  test::TempDir dir;
  const std::string path = dir.write("out.txt", "old");
  for (size_t size : {size_t(3000), size_t(1 << 20)}) {
    std::optional<Error> e;
    {
      FileSizeLimit limit(2000);
      e = write_file_atomic(path, std::string(size, 'x'));
    }
    ASSERT_TRUE(e) << size << " bytes";
    EXPECT_EQ(e->message, path + ": write failed: " + std::strerror(EFBIG)) << size << " bytes";
    EXPECT_EQ(test::read_file(path), "old");
    expect_only(dir, "out.txt");
  }
}

TEST(AtomicFile, ARefusedRenameLeavesNothingBehind) {
  test::TempDir dir;
  const std::string path = dir / "taken";
  std::filesystem::create_directory(path);  // rename(2) does not put a file in a directory's place (EISDIR)
  std::optional<Error> e = write_file_atomic(path, "bytes");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->message.rfind(path + ": cannot rename into place: ", 0), 0u) << e->message;
  EXPECT_TRUE(std::filesystem::is_directory(path));
  expect_only(dir, "taken");
}

TEST(AtomicFile, AFileThatCannotBeOpenedIsNamed) {
  test::TempDir dir;
  const std::string path = dir / "missing/out.txt";
  std::optional<Error> e = write_file_atomic(path, "bytes");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->message, path + ": cannot open for writing: " + std::strerror(ENOENT));
  EXPECT_TRUE(std::filesystem::is_empty(dir.path));
}

}  // namespace
}  // namespace pt
