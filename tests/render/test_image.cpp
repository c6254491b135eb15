// Image files and the display transform: tonemap curves, the IEC 61966-2-1 sRGB curve, PNG quantisation, bit-exact
// PFM/EXR round trips (byte layout checked against the PFM and OpenEXR definitions with files built byte by byte),
// strict PFM header validation, and write atomicity (no partial or temporary files after any failure).
#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "fifo_watchdog.h"
#include "render/image.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using pt::DisplaySettings;
using pt::Image;
using pt::Tonemap;
using pt::vec3;
using pt::test::read_file;

namespace {

/// A fresh, empty directory per test, removed afterwards.
class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("ptview_test_image_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

void write_bytes(const std::string& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

// Byte encodings built with shifts, so they do not depend on the host's endianness.
std::string le32(uint32_t v) {
  return {char(v & 0xff), char((v >> 8) & 0xff), char((v >> 16) & 0xff), char((v >> 24) & 0xff)};
}
std::string be32(uint32_t v) {
  return {char((v >> 24) & 0xff), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
}
std::string le_float(float f) { return le32(std::bit_cast<uint32_t>(f)); }
std::string be_float(float f) { return be32(std::bit_cast<uint32_t>(f)); }
std::string le64(uint64_t v) { return le32(uint32_t(v)) + le32(uint32_t(v >> 32)); }

bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// Reference IEC 61966-2-1 decoding (the inverse of the encoding under test), in double precision.
double srgb_decode(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

/// A 7x3 image whose samples span signs and magnitudes, including a denormal, and whose first stored PFM byte
/// (bottom-left red, low byte in little-endian order) is '\n', so a reader that skips extra whitespace fails.
Image awkward_image() {
  const float specials[] = {-3.5f, 1.0e30f, 1.0e-30f, 1.0e-42f, -0.0f, 65504.0f, 0.1f, -1.0e-7f, 123456.789f};
  Image img(7, 3);
  for (size_t i = 0; i < img.rgb.size(); ++i)
    img.rgb[i] = specials[i % std::size(specials)] * (1.0f + 0.03125f * float(i));
  img.rgb[size_t(2) * 7 * 3] = std::bit_cast<float>(0x3f80000aU);
  return img;
}

void expect_bit_equal(const Image& a, const Image& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (size_t i = 0; i < a.rgb.size(); ++i)
    EXPECT_EQ(std::bit_cast<uint32_t>(a.rgb[i]), std::bit_cast<uint32_t>(b.rgb[i])) << "sample " << i;
}

/// An uncompressed single-part scanline OpenEXR file with FLOAT channels, written per the OpenEXR file layout
/// ("OpenEXR File Layout", openexr.com): magic, version, attributes, line offset table, one scanline per chunk.
/// `channels` maps names to top-first row-major samples; std::map keeps them in the required sorted order.
std::string build_exr(int w, int h, int x0, int y0, const std::map<std::string, std::vector<float>>& channels) {
  auto attribute = [](const std::string& name, const std::string& type, const std::string& value) {
    return name + '\0' + type + '\0' + le32(uint32_t(value.size())) + value;
  };
  std::string chlist;
  for (const auto& [name, data] : channels) chlist += name + '\0' + le32(2) + std::string(4, '\0') + le32(1) + le32(1);
  chlist += '\0';
  const std::string box =
      le32(uint32_t(x0)) + le32(uint32_t(y0)) + le32(uint32_t(x0 + w - 1)) + le32(uint32_t(y0 + h - 1));
  std::string file = std::string("\x76\x2f\x31\x01", 4) + le32(2);
  file += attribute("channels", "chlist", chlist);
  file += attribute("compression", "compression", std::string(1, '\0'));
  file += attribute("dataWindow", "box2i", box);
  file += attribute("displayWindow", "box2i", box);
  file += attribute("lineOrder", "lineOrder", std::string(1, '\0'));
  file += attribute("pixelAspectRatio", "float", le_float(1.0f));
  file += attribute("screenWindowCenter", "v2f", le_float(0.0f) + le_float(0.0f));
  file += attribute("screenWindowWidth", "float", le_float(1.0f));
  file += '\0';
  const size_t chunk = 8 + channels.size() * size_t(w) * 4;
  const size_t first = file.size() + size_t(h) * 8;
  for (int y = 0; y < h; ++y) file += le64(first + size_t(y) * chunk);
  for (int y = 0; y < h; ++y) {
    file += le32(uint32_t(y0 + y)) + le32(uint32_t(chunk - 8));
    for (const auto& [name, data] : channels)
      for (int x = 0; x < w; ++x) file += le_float(data[size_t(y) * size_t(w) + size_t(x)]);
  }
  return file;
}

// ---- Tonemaps and the sRGB curve ---------------------------------------------------------------------------------

TEST(Tonemap, ClampIsPerChannelMinWithOne) {
  const vec3 c = pt::apply_tonemap({0.3f, 1.0f, 5.0f}, {0.0f, Tonemap::clamp});
  EXPECT_FLOAT_EQ(c.x, 0.3f);
  EXPECT_FLOAT_EQ(c.y, 1.0f);
  EXPECT_FLOAT_EQ(c.z, 1.0f);
}

TEST(Tonemap, ReinhardIsXOverOnePlusX) {
  const vec3 c = pt::apply_tonemap({1.0f, 3.0f, 0.25f}, {0.0f, Tonemap::reinhard});
  EXPECT_FLOAT_EQ(c.x, 0.5f);
  EXPECT_FLOAT_EQ(c.y, 0.75f);
  EXPECT_FLOAT_EQ(c.z, 0.2f);
  const float big = pt::apply_tonemap(vec3(1.0e30f), {0.0f, Tonemap::reinhard}).x;
  EXPECT_LE(big, 1.0f);
  EXPECT_GT(big, 0.999f);
}

TEST(Tonemap, ExposureScalesByPowersOfTwo) {
  EXPECT_FLOAT_EQ(pt::apply_tonemap(vec3(0.25f), {1.0f, Tonemap::clamp}).x, 0.5f);
  EXPECT_FLOAT_EQ(pt::apply_tonemap(vec3(1.0f), {-2.0f, Tonemap::clamp}).x, 0.25f);
  EXPECT_FLOAT_EQ(pt::apply_tonemap(vec3(0.5f), {1.0f, Tonemap::reinhard}).x, 0.5f);
  EXPECT_FLOAT_EQ(pt::apply_tonemap(vec3(0.25f), {2.0f, Tonemap::aces}).x,
                  pt::apply_tonemap(vec3(1.0f), {0.0f, Tonemap::aces}).x);
}

TEST(Tonemap, AcesIsMonotonicAndBounded) {
  const DisplaySettings aces{0.0f, Tonemap::aces};
  EXPECT_EQ(pt::apply_tonemap(vec3(0.0f), aces).x, 0.0f);
  // Narkowicz 2015 at x = 1: (2.51 + 0.03) / (2.43 + 0.59 + 0.14).
  EXPECT_NEAR(pt::apply_tonemap(vec3(1.0f), aces).x, 2.54 / 3.16, 1e-6);
  float previous = 0.0f;
  for (int i = 1; i <= 20000; ++i) {
    const float x = 0.001f * float(i);
    const float y = pt::apply_tonemap(vec3(x), aces).x;
    ASSERT_GE(y, 0.0f) << x;
    ASSERT_LE(y, 1.0f) << x;
    ASSERT_GE(y, previous) << x;
    if (x < 7.0f) {  // strictly increasing until the curve reaches 1 near x = 7.25
      ASSERT_GT(y, previous) << x;
    }
    previous = y;
  }
  EXPECT_EQ(pt::apply_tonemap(vec3(1.0e30f), aces).x, 1.0f);
}

TEST(Tonemap, NegativeNaNAndInfiniteInputsStayInRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (Tonemap t : {Tonemap::clamp, Tonemap::reinhard, Tonemap::aces}) {
    for (float exposure : {0.0f, 3.0f}) {
      const vec3 c = pt::apply_tonemap({nan, -2.0f, -inf}, {exposure, t});
      EXPECT_EQ(c.x, 0.0f);
      EXPECT_EQ(c.y, 0.0f);
      EXPECT_EQ(c.z, 0.0f);
      const vec3 d = pt::apply_tonemap({inf, 0.5f, nan}, {exposure, t});
      EXPECT_EQ(d.x, 1.0f) << int(t);
      EXPECT_GT(d.y, 0.0f);
      EXPECT_EQ(d.z, 0.0f);
    }
  }
}

TEST(Srgb, KnownPointsOfTheIecCurve) {
  EXPECT_EQ(pt::srgb_encode(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(pt::srgb_encode(1.0f), 1.0f);
  EXPECT_FLOAT_EQ(pt::srgb_encode(0.001f), 0.01292f);                // linear segment
  EXPECT_FLOAT_EQ(pt::srgb_encode(0.0031308f), 12.92f * 0.0031308f);  // last point of the linear segment
  EXPECT_NEAR(pt::srgb_encode(0.5f), 0.735357, 1e-6);
  // The two pieces meet at the boundary (to the precision of the published constants).
  EXPECT_NEAR(pt::srgb_encode(std::nextafter(0.0031308f, 1.0f)), pt::srgb_encode(0.0031308f), 1e-6);
  EXPECT_EQ(pt::srgb_encode(-0.5f), 0.0f);
  EXPECT_EQ(pt::srgb_encode(std::numeric_limits<float>::quiet_NaN()), 0.0f);
  for (int i = 0; i <= 1000; ++i) {  // the IEC decoding inverts it everywhere
    const double x = i / 1000.0;
    EXPECT_NEAR(srgb_decode(pt::srgb_encode(float(x))), x, 2e-6) << x;
  }
}

// ---- PFM ---------------------------------------------------------------------------------------------------------

TEST_F(ImageFiles, PfmRoundTripIsBitExactAndStoresBottomRowFirst) {
  const Image img = awkward_image();
  const std::string p = path("round.pfm");
  ASSERT_FALSE(pt::save_image(p, img).has_value());
  const std::string bytes = read_file(p);
  const std::string header = "PF\n7 3\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + 7 * 3 * 3 * 4);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  for (int stored = 0; stored < 3; ++stored) {
    const int y = 2 - stored;  // the first stored row is the bottom one
    std::string expected;
    for (int x = 0; x < 7; ++x)
      for (int c = 0; c < 3; ++c) expected += le_float(img.at(x, y)[c]);
    EXPECT_EQ(bytes.substr(header.size() + size_t(stored) * 7 * 12, 7 * 12), expected) << "stored row " << stored;
  }
  const pt::Result<Image> back = pt::load_image(p);
  ASSERT_TRUE(back.ok()) << back.error();
  expect_bit_equal(img, *back);
  EXPECT_EQ(listing(), std::vector<std::string>{"round.pfm"});
}

TEST_F(ImageFiles, ReadsBigEndianPfm) {
  // 2x2, rows stored bottom first; positive scale = big-endian.
  const float bottom[6] = {1.5f, -2.0f, 3.25f, 1e20f, 0.0f, -1e-20f}, top[6] = {7.0f, 8.0f, 9.0f, 10.0f, 11.0f, 12.0f};
  std::string file = "PF\n2 2\n1.0\n";
  for (float v : bottom) file += be_float(v);
  for (float v : top) file += be_float(v);
  write_bytes(path("be.pfm"), file);
  const pt::Result<Image> img = pt::load_image(path("be.pfm"));
  ASSERT_TRUE(img.ok()) << img.error();
  ASSERT_EQ(img->width, 2);
  ASSERT_EQ(img->height, 2);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(img->rgb[size_t(i)], top[i]);
    EXPECT_EQ(img->rgb[6 + size_t(i)], bottom[i]);
  }
}

TEST_F(ImageFiles, ReadsGreyscalePfmAsGreyRgb) {
  const float rows[2][3] = {{0.25f, -1.0f, 4.0f}, {100.0f, 1e-3f, 0.5f}};  // bottom row first in the file
  std::string file = "Pf\n3 2\n-1.0\n";
  for (const auto& row : rows)
    for (float v : row) file += le_float(v);
  write_bytes(path("grey.pfm"), file);
  const pt::Result<Image> img = pt::load_image(path("grey.pfm"));
  ASSERT_TRUE(img.ok()) << img.error();
  ASSERT_EQ(img->width, 3);
  ASSERT_EQ(img->height, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      const float v = rows[1 - y][x];
      EXPECT_EQ(img->at(x, y), vec3(v)) << x << "," << y;
    }
}

TEST_F(ImageFiles, PfmScaleMagnitudeMultipliesSamples) {
  write_bytes(path("half.pfm"), "PF\n1 1\n-0.5\n" + le_float(2.0f) + le_float(-4.0f) + le_float(8.0f));
  const pt::Result<Image> img = pt::load_image(path("half.pfm"));
  ASSERT_TRUE(img.ok()) << img.error();
  EXPECT_EQ(img->at(0, 0), vec3(1.0f, -2.0f, 4.0f));
}

TEST_F(ImageFiles, MalformedPfmHeadersAreErrorsNamingTheFile) {
  const std::string pixel = le_float(1.0f) + le_float(2.0f) + le_float(3.0f);
  // Control: the well-formed file these cases are mutations of.
  write_bytes(path("good.pfm"), "PF\n1 1\n-1.0\n" + pixel);
  ASSERT_TRUE(pt::load_image(path("good.pfm")).ok());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"truncated", "PF\n2 2\n-1.0\n" + std::string(47, '\0')},
      {"bad_magic", "P6\n1 1\n-1.0\n" + pixel},
      {"magic_not_separated", "PFX\n1 1\n-1.0\n" + pixel},
      {"magic_runs_into_the_size", "PF1 1\n-1.0\n" + pixel},  // would read as 1x1 without the separator
      {"zero_width", "PF\n0 1\n-1.0\n" + pixel},
      {"zero_height", "PF\n1 0\n-1.0\n" + pixel},
      {"negative_width", "PF\n-1 1\n-1.0\n" + pixel},
      {"absurd_size", "PF\n100000 100000\n-1.0\n" + pixel},
      {"just_over_limit", "PF\n65537 1\n-1.0\n" + std::string(65537 * 12, '\0')},  // data complete, size too big
      {"overflowing_size", "PF\n99999999999999999999 1\n-1.0\n" + pixel},
      {"non_numeric_size", "PF\n1x 1\n-1.0\n" + pixel},
      {"garbage_scale", "PF\n1 1\nabc\n" + pixel},
      {"zero_scale", "PF\n1 1\n0.0\n" + pixel},
      {"nan_scale", "PF\n1 1\nnan\n" + pixel},
      {"inf_scale", "PF\n1 1\n-inf\n" + pixel},
      {"trailing_junk_scale", "PF\n1 1\n-1.0x\n" + pixel},
      {"header_only", "PF\n1 1\n-1.0"},
      {"empty", ""},
  };
  for (const auto& [name, bytes] : cases) {
    const std::string p = path(name + ".pfm");
    write_bytes(p, bytes);
    const pt::Result<Image> img = pt::load_image(p);
    EXPECT_FALSE(img.ok()) << name;
    EXPECT_TRUE(starts_with(img.error(), p + ": ")) << name << ": " << img.error();
  }
}

// A header token is read up to 32 bytes: a megabyte of garbage without whitespace after "PF" (a binary file given a
// .pfm name) gives a one-line error of ordinary length, not one that quotes all of it.
TEST_F(ImageFiles, AnOverlongPfmHeaderTokenIsNotQuotedWhole) {
  const std::string p = path("long.pfm");
  write_bytes(p, "PF\n" + std::string(1 << 20, '7') + " 1\n-1.0\n" + std::string(12, '\0'));
  const pt::Result<Image> img = pt::load_image(p);
  ASSERT_FALSE(img.ok());
  EXPECT_TRUE(starts_with(img.error(), p + ": missing or invalid PFM size")) << img.error().substr(0, 200);
  EXPECT_LT(img.error().size(), p.size() + 200);
}

TEST_F(ImageFiles, LoadErrorsNameTheFile) {
  const std::string missing = path("missing.pfm");
  const pt::Result<Image> a = pt::load_image(missing);
  ASSERT_FALSE(a.ok());
  EXPECT_TRUE(starts_with(a.error(), missing + ": ")) << a.error();
  EXPECT_TRUE(contains(a.error(), "No such file or directory")) << a.error();
  write_bytes(path("x.png"), "not really");
  const pt::Result<Image> b = pt::load_image(path("x.png"));
  ASSERT_FALSE(b.ok());
  EXPECT_TRUE(starts_with(b.error(), path("x.png") + ": ")) << b.error();
}

// Only a regular file is read. A directory is refused by name, and a FIFO (say a --reference given a named pipe) is
// refused without waiting for a writer: opening one for reading blocks until a writer comes, so the reader opens
// without blocking and looks at what it opened first. A 20 s watchdog opens the FIFO for writing if a regression
// makes the load wait on it, so the test fails rather than hangs.
TEST_F(ImageFiles, DirectoryAndFifoAreRefusedUnread) {
  const std::string folder = path("folder.pfm");
  ASSERT_TRUE(fs::create_directory(folder));
  const pt::Result<Image> d = pt::load_image(folder);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error(), folder + ": cannot open: is a directory");
  const std::string fifo = path("pipe.exr");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const pt::Result<Image> f = pt::test::load_with_fifo_watchdog(fifo, [&] { return pt::load_image(fifo); });
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error(), fifo + ": cannot open: not a regular file");
}

// ---- EXR ---------------------------------------------------------------------------------------------------------

TEST_F(ImageFiles, ExrRoundTripIsExact) {
  const Image img = awkward_image();
  const std::string p = path("round.exr");
  ASSERT_FALSE(pt::save_image(p, img).has_value());
  EXPECT_EQ(read_file(p).substr(0, 4), std::string("\x76\x2f\x31\x01", 4));  // OpenEXR magic number
  const pt::Result<Image> back = pt::load_image(p);
  ASSERT_TRUE(back.ok()) << back.error();
  expect_bit_equal(img, *back);
}

TEST_F(ImageFiles, ReadsHandBuiltExrWithOffsetDataWindow) {
  const std::vector<float> r = {1, 2, 3, 4, 5, 6}, g = {-1, -2, -3, -4, -5, -6}, b = {0.5f, 1e-20f, 1e20f, 0, 7, 8};
  write_bytes(path("rgb.exr"), build_exr(3, 2, 10, 20, {{"R", r}, {"G", g}, {"B", b}}));
  const pt::Result<Image> img = pt::load_image(path("rgb.exr"));
  ASSERT_TRUE(img.ok()) << img.error();
  ASSERT_EQ(img->width, 3);
  ASSERT_EQ(img->height, 2);
  for (size_t i = 0; i < 6; ++i) EXPECT_EQ(img->at(int(i % 3), int(i / 3)), vec3(r[i], g[i], b[i])) << i;
}

TEST_F(ImageFiles, ExrLuminanceOnlyIsGreyAndMissingChannelsAreZero) {
  const std::vector<float> y = {0.25f, 2.0f, -1.0f, 8.0f};
  write_bytes(path("y.exr"), build_exr(2, 2, 5, -3, {{"Y", y}}));
  const pt::Result<Image> grey = pt::load_image(path("y.exr"));
  ASSERT_TRUE(grey.ok()) << grey.error();
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(grey->at(int(i % 2), int(i / 2)), vec3(y[i])) << i;

  write_bytes(path("rb.exr"), build_exr(2, 2, -7, 4, {{"B", y}, {"R", y}}));
  const pt::Result<Image> rb = pt::load_image(path("rb.exr"));
  ASSERT_TRUE(rb.ok()) << rb.error();
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(rb->at(int(i % 2), int(i / 2)), vec3(y[i], 0.0f, y[i])) << i;

  write_bytes(path("z.exr"), build_exr(2, 2, 0, 0, {{"Z", y}}));
  const pt::Result<Image> z = pt::load_image(path("z.exr"));
  ASSERT_FALSE(z.ok());
  EXPECT_TRUE(starts_with(z.error(), path("z.exr") + ": ")) << z.error();
}

TEST_F(ImageFiles, ExrWiderThanTheLimitIsRefusedBeforeItsPixelsAreRead) {
  // A well-formed file 100,000 pixels wide: past the 65,536 per side that guards allocations against hostile
  // headers, whose data window alone would otherwise size the image (2^31 x 2^31 pixels take four bytes of header).
  write_bytes(path("wide.exr"), build_exr(100000, 1, 0, 0, {{"Y", std::vector<float>(100000, 1.0f)}}));
  const pt::Result<Image> img = pt::load_image(path("wide.exr"));
  ASSERT_FALSE(img.ok());
  EXPECT_TRUE(starts_with(img.error(), path("wide.exr") + ": EXR data window 100000x1 out of range")) << img.error();
}

TEST_F(ImageFiles, CorruptExrIsAnErrorNotAnException) {
  const std::string good = build_exr(2, 2, 0, 0, {{"Y", {1, 2, 3, 4}}});
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"truncated.exr", good.substr(0, good.size() - 10)},
           {"header_cut.exr", good.substr(0, 40)},
           {"garbage.exr", std::string(200, 'x')}}) {
    write_bytes(path(name), bytes);
    pt::Result<Image> img(Image{});
    EXPECT_NO_THROW(img = pt::load_image(path(name))) << name;
    EXPECT_FALSE(img.ok()) << name;
    EXPECT_TRUE(starts_with(img.error(), path(name) + ": ")) << img.error();
  }
}

// ---- PNG ---------------------------------------------------------------------------------------------------------

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};
Png read_png(const std::string& p) {
  Png png;
  int channels = 0;
  unsigned char* data = stbi_load(p.c_str(), &png.width, &png.height, &channels, 3);
  if (data) png.rgb.assign(data, data + size_t(png.width) * size_t(png.height) * 3);
  stbi_image_free(data);
  return png;
}

TEST_F(ImageFiles, PngHoldsRoundedSrgbOfTheTonemappedImageTopRowFirst) {
  Image img(4, 2);
  img.set(0, 0, {0.5f, 0.0f, 1.0f});
  img.set(1, 0, {2.0f, -1.0f, 0.0031308f});
  img.set(2, 0, {0.25f, 0.214f, 0.0f});
  img.set(3, 0, {std::numeric_limits<float>::quiet_NaN(), 0.01f, 0.9f});
  for (int x = 0; x < 4; ++x) img.set(x, 1, vec3(0.0f));  // dark bottom row: catches a vertical flip
  const std::string p = path("out.png");
  ASSERT_FALSE(pt::save_image(p, img).has_value());
  const Png png = read_png(p);
  ASSERT_EQ(png.width, 4);
  ASSERT_EQ(png.height, 2);
  EXPECT_EQ(png.rgb[0], 188);  // sRGB(0.5) = 0.735357 -> 187.99 + 0.5
  EXPECT_EQ(png.rgb[1], 0);
  EXPECT_EQ(png.rgb[2], 255);
  EXPECT_EQ(png.rgb[3], 255);  // 2.0 clamps
  EXPECT_EQ(png.rgb[4], 0);    // negative -> 0
  EXPECT_EQ(png.rgb[5], 10);   // 12.92 * 0.0031308 * 255 = 10.31
  EXPECT_EQ(png.rgb[9], 0);    // NaN -> 0
  // Every stored code is the nearest 8-bit value to the exact sRGB encoding (within rounding of the half step).
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) {
      const float v = img.at(x, 0)[c];
      if (!(v >= 0.0f && v <= 1.0f)) continue;
      const double exact = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(double(v), 1 / 2.4) - 0.055;
      EXPECT_LE(std::abs(exact * 255.0 - png.rgb[size_t(x) * 3 + size_t(c)]), 0.5 + 1e-4) << x << "," << c;
    }
  for (size_t i = 12; i < 24; ++i) EXPECT_EQ(png.rgb[i], 0) << i;
}

TEST_F(ImageFiles, PngAppliesExposureAndTonemap) {
  Image img(2, 1);
  img.set(0, 0, vec3(0.25f));
  img.set(1, 0, vec3(0.5f));
  ASSERT_FALSE(pt::save_image(path("exposed.png"), img, {1.0f, Tonemap::clamp}).has_value());
  const Png a = read_png(path("exposed.png"));
  ASSERT_EQ(a.rgb.size(), 6u);
  EXPECT_EQ(a.rgb[0], 188);  // 0.25 * 2 = 0.5
  EXPECT_EQ(a.rgb[3], 255);  // 0.5 * 2 = 1
  ASSERT_FALSE(pt::save_image(path("reinhard.png"), img, {1.0f, Tonemap::reinhard}).has_value());
  const Png b = read_png(path("reinhard.png"));
  ASSERT_EQ(b.rgb.size(), 6u);
  EXPECT_EQ(b.rgb[0], 156);  // reinhard(0.5) = 1/3 -> sRGB 0.6105 -> 155.69 + 0.5
  EXPECT_EQ(b.rgb[3], 188);  // reinhard(1) = 0.5
}

// ---- Extensions and atomicity ------------------------------------------------------------------------------------

TEST(ImageExtensions, RecognisedCaseInsensitively) {
  for (const char* p : {"a.png", "a.PNG", "dir/b.Pfm", "c.exr", "x.y.EXR"})
    EXPECT_TRUE(pt::is_supported_image_extension(p)) << p;
  for (const char* p : {"a.jpg", "png", "", "a.png.gz", "a.png/", "a.exrx", "dir.png/file"})
    EXPECT_FALSE(pt::is_supported_image_extension(p)) << p;
}

TEST_F(ImageFiles, UpperCaseExtensionsPickTheFormat) {
  const Image img = awkward_image();
  ASSERT_FALSE(pt::save_image(path("A.PFM"), img).has_value());
  EXPECT_TRUE(starts_with(read_file(path("A.PFM")), "PF\n7 3\n"));
  ASSERT_FALSE(pt::save_image(path("B.Png"), img).has_value());
  EXPECT_EQ(read_file(path("B.Png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

TEST_F(ImageFiles, WritingIntoAMissingDirectoryFailsAndCreatesNothing) {
  const Image img(2, 2);
  for (const char* name : {"x.png", "x.pfm", "x.exr"}) {
    const std::string p = path(std::string("missing/") + name);
    const std::optional<pt::Error> err = pt::save_image(p, img);
    ASSERT_TRUE(err.has_value()) << name;
    EXPECT_EQ(err->message, p + ": cannot open for writing: No such file or directory");
  }
  EXPECT_TRUE(listing().empty());
}

TEST_F(ImageFiles, WritingOverAnExistingFileReplacesIt) {
  const Image img = awkward_image();
  for (const char* name : {"x.pfm", "x.exr"}) {
    write_bytes(path(name), "stale contents that are not an image");
    ASSERT_FALSE(pt::save_image(path(name), img).has_value()) << name;
    const pt::Result<Image> back = pt::load_image(path(name));
    ASSERT_TRUE(back.ok()) << back.error();
    expect_bit_equal(img, *back);
  }
  write_bytes(path("x.png"), std::string(100000, 'z'));  // longer than the PNG: a non-truncating write would show
  ASSERT_FALSE(pt::save_image(path("x.png"), img).has_value());
  EXPECT_EQ(read_png(path("x.png")).width, 7);
  EXPECT_EQ(listing(), (std::vector<std::string>{"x.exr", "x.pfm", "x.png"}));
}

TEST_F(ImageFiles, FailedWritesLeaveNoFilesBehind) {
  const Image img(3, 2);
  Image bad_size(3, 2);
  bad_size.rgb.pop_back();
  const std::vector<std::pair<std::string, Image>> cases = {
      {"x.bmp", img}, {"noext", img}, {"empty.pfm", Image{}}, {"empty.png", Image(0, 4)}, {"short.exr", bad_size}};
  for (const auto& [name, image] : cases) {
    const std::optional<pt::Error> err = pt::save_image(path(name), image);
    ASSERT_TRUE(err.has_value()) << name;
    EXPECT_TRUE(starts_with(err->message, path(name) + ": ")) << err->message;
  }
  EXPECT_TRUE(listing().empty());
  // The destination is a directory: the temporary file is written, the rename fails, and it must be removed.
  for (const char* name : {"d.png", "d.pfm", "d.exr"}) {
    fs::create_directory(path(name));
    const std::optional<pt::Error> err = pt::save_image(path(name), img);
    ASSERT_TRUE(err.has_value()) << name;
    EXPECT_TRUE(starts_with(err->message, path(name) + ": ")) << err->message;
    EXPECT_TRUE(fs::is_empty(path(name))) << name;
  }
  EXPECT_EQ(listing(), (std::vector<std::string>{"d.exr", "d.pfm", "d.png"}));
}

TEST_F(ImageFiles, ReadOnlyDirectoryFailsWithoutTempFiles) {
  // Failures that happen for root too (CI runs as root, which ignores directory permissions).
  // 1. The parent "directory" is a regular file: the temporary file cannot even be created.
  write_bytes(path("plain"), "x");
  std::optional<pt::Error> err = pt::save_image(path("plain") + "/keep.pfm", Image(2, 2));
  ASSERT_TRUE(err.has_value());
  EXPECT_TRUE(contains(err->message, "plain/keep.pfm")) << err->message;
  EXPECT_EQ(read_file(path("plain")), "x");
  // 2. The target is a non-empty directory: the temporary file is written, the rename fails, and the temporary
  //    file must be removed, leaving the directory as it was.
  fs::create_directories(dir_ / "taken.pfm");
  write_bytes(path("taken.pfm/inside"), "y");
  for (const char* ext : {"pfm", "png", "exr"}) {
    fs::create_directories(dir_ / (std::string("taken.") + ext));
    err = pt::save_image(path(std::string("taken.") + ext), Image(2, 2));
    ASSERT_TRUE(err.has_value()) << ext;
    EXPECT_TRUE(contains(err->message, std::string("taken.") + ext)) << err->message;
  }
  EXPECT_EQ(read_file(path("taken.pfm/inside")), "y");
  EXPECT_EQ(listing(), (std::vector<std::string>{"plain", "taken.exr", "taken.pfm", "taken.png"}));
  // 3. As a non-root user, also a read-only directory.
  if (::geteuid() != 0) {
    fs::create_directories(dir_ / "ro");
    write_bytes(path("ro/keep.pfm"), "old");
    fs::permissions(dir_ / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    err = pt::save_image(path("ro/keep.pfm"), Image(2, 2));
    fs::permissions(dir_ / "ro", fs::perms::owner_all);
    ASSERT_TRUE(err.has_value());
    EXPECT_TRUE(contains(err->message, "Permission denied")) << err->message;
    EXPECT_EQ(read_file(path("ro/keep.pfm")), "old");
  }
}

TEST_F(ImageFiles, ConcurrentWritersNeverExposeAPartialFile) {
  Image a(32, 32), b(32, 32);
  std::fill(a.rgb.begin(), a.rgb.end(), 1.0f);
  std::fill(b.rgb.begin(), b.rgb.end(), 2.0f);
  const std::string p = path("shared.pfm");
  auto writer = [&](const Image& img) {
    for (int i = 0; i < 25; ++i) EXPECT_FALSE(pt::save_image(p, img).has_value());
  };
  std::thread t1(writer, std::cref(a)), t2(writer, std::cref(b));
  t1.join();
  t2.join();
  const pt::Result<Image> back = pt::load_image(p);
  ASSERT_TRUE(back.ok()) << back.error();
  const float first = back->rgb[0];
  EXPECT_TRUE(first == 1.0f || first == 2.0f);
  for (float v : back->rgb) ASSERT_EQ(v, first);  // one writer's whole file, never a mixture
  EXPECT_EQ(listing(), std::vector<std::string>{"shared.pfm"});
}

}  // namespace
