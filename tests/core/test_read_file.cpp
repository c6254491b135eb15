// The one whole-file reader (core/read_file.h) behind the scene loaders and the image reader: exact bytes, and each
// refusal one error naming the file and its reason. The FIFO cases of its users (tests/scene/test_load.cpp,
// tests/render/test_image.cpp) check that nothing waits on a pipe.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/read_file.h"
#include "temp_dir.h"

namespace pt {
namespace {

constexpr uint64_t kNoLimit = ~uint64_t(0);

TEST(ReadWholeFile, ReturnsEveryByteOfARegularFile) {
  test::TempDir dir;
  const std::string bytes = std::string("a\0b\r\n\xff", 6) + std::string(100000, 'z');
  const Result<std::string> r = read_whole_file(dir.write("f.bin", bytes), kNoLimit);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(*r, bytes);
  const Result<std::string> empty = read_whole_file(dir.write("e.txt", ""), kNoLimit);
  ASSERT_TRUE(empty.ok()) << empty.error();
  EXPECT_EQ(*empty, "");
}

TEST(ReadWholeFile, RefusalsNameTheFileAndTheReason) {
  test::TempDir dir;
  const std::string missing = dir / "missing.obj";
  const Result<std::string> a = read_whole_file(missing, kNoLimit);
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.error(), missing + ": cannot open: No such file or directory");
  const Result<std::string> b = read_whole_file(dir.path.string(), kNoLimit);
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(b.error(), dir.path.string() + ": cannot open: is a directory");
  const Result<std::string> c = read_whole_file("/dev/null", kNoLimit);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.error(), "/dev/null: cannot open: not a regular file");
}

TEST(ReadWholeFile, AFileAboveTheLimitIsRefusedUnread) {
  test::TempDir dir;
  const std::string ten = dir.write("ten.txt", "0123456789");
  EXPECT_TRUE(read_whole_file(ten, 10).ok());  // the limit itself is allowed
  const Result<std::string> r = read_whole_file(ten, 9);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), ten + ": cannot open: larger than 9 bytes");
  // A whole number of GiB is said so; a sparse file takes no disk space.
  const std::string big = dir.write("big.txt", "");
  std::filesystem::resize_file(big, (uint64_t(1) << 30) + 1);
  const Result<std::string> g = read_whole_file(big, uint64_t(1) << 30);
  ASSERT_FALSE(g.ok());
  EXPECT_EQ(g.error(), big + ": cannot open: larger than 1 GiB");
}

}  // namespace
}  // namespace pt
