/// Image files: display transform (exposure, tonemap, sRGB), atomic writes, and the PNG / PFM / EXR codecs.
/// Every encoder produces the whole file in memory first; write_file_atomic (core/atomic_file.h) then puts it in
/// place, so a failure at any stage leaves neither a partial file nor a temporary one behind.
#include "render/image.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <IexBaseExc.h>
#include <stb_image_write.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <string_view>

#include "core/atomic_file.h"
#include "core/file_name.h"
#include "core/read_file.h"

namespace pt {

namespace {

/// Largest width or height we read: guards allocations against corrupt or hostile headers.
constexpr int kMaxImageDimension = 65536;

Error file_error(const std::string& path, const std::string& reason) { return Error{path + ": " + reason}; }

// ---- PFM (Portable Float Map; Debevec's format, as read by pbrt-v4 Image::ReadPFM) -------------------------------

uint32_t byte_swap(uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

/// PF header, then little-endian float32 RGB rows from the bottom row to the top (the PFM row order).
std::string encode_pfm(const Image& image) {
  const std::string header = "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
  const size_t row_floats = size_t(image.width) * 3;
  std::string out = header;
  out.resize(header.size() + row_floats * size_t(image.height) * 4);
  char* dst = out.data() + header.size();
  for (int y = image.height - 1; y >= 0; --y) {
    const float* src = image.rgb.data() + size_t(y) * row_floats;
    for (size_t i = 0; i < row_floats; ++i, dst += 4) {
      uint32_t bits = std::bit_cast<uint32_t>(src[i]);
      if constexpr (std::endian::native == std::endian::big) bits = byte_swap(bits);
      std::memcpy(dst, &bits, 4);
    }
  }
  return out;
}

bool is_pfm_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/// Strict PFM reader: "PF" (RGB) or "Pf" (grey), whitespace-separated positive width and height, a finite nonzero
/// scale (negative: little-endian data, positive: big-endian; |scale| multiplies the samples, as in pbrt-v4), one
/// whitespace byte, then bottom-to-top rows. Greyscale is expanded to RGB; rows are flipped to top-first.
Result<Image> decode_pfm(const std::string& path, const std::string& bytes) {
  const size_t n = bytes.size();
  if (n < 3 || bytes[0] != 'P' || (bytes[1] != 'F' && bytes[1] != 'f') || !is_pfm_space(bytes[2]))
    return file_error(path, "not a PFM file (expected \"PF\" or \"Pf\" magic)");
  const int channels = bytes[1] == 'F' ? 3 : 1;
  size_t pos = 2;
  // Next header token: skips leading whitespace and stops at the whitespace byte that must end it (not consumed).
  // Empty if the token is missing, overlong or not followed by whitespace.
  auto token = [&]() -> std::string_view {
    while (pos < n && is_pfm_space(bytes[pos])) ++pos;
    const size_t start = pos;
    while (pos < n && !is_pfm_space(bytes[pos]) && pos - start < 32) ++pos;
    if (pos >= n || !is_pfm_space(bytes[pos])) return {};
    return {bytes.data() + start, pos - start};
  };
  auto dimension = [&](std::string_view t) {
    int v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    bool digits_only = !t.empty() && t[0] != '-';
    return ec == std::errc() && end == t.data() + t.size() && digits_only ? v : -1;
  };
  const std::string_view wtok = token(), htok = token();
  const int width = dimension(wtok), height = dimension(htok);
  if (width <= 0 || height <= 0)
    return file_error(path, "missing or invalid PFM size \"" + std::string(wtok) + " " + std::string(htok) + "\"");
  if (width > kMaxImageDimension || height > kMaxImageDimension)
    return file_error(path, "PFM size " + std::to_string(width) + "x" + std::to_string(height) + " exceeds " +
                                std::to_string(kMaxImageDimension) + " per side");
  const std::string_view stok = token();
  float scale = 0.0f;
  const auto [send, sec] = std::from_chars(stok.data(), stok.data() + stok.size(), scale);
  if (sec != std::errc() || send != stok.data() + stok.size() || !std::isfinite(scale) || scale == 0.0f)
    return file_error(path, "missing or invalid PFM scale \"" + std::string(stok) + "\" (need finite, nonzero)");
  ++pos;  // exactly one whitespace byte separates the header from the raster
  const size_t count = size_t(width) * size_t(height) * size_t(channels);
  if (n - pos < count * 4)
    return file_error(path, "truncated PFM pixel data (expected " + std::to_string(count * 4) + " bytes, found " +
                                std::to_string(n - pos) + ")");
  const bool swap = (scale < 0.0f) != (std::endian::native == std::endian::little);
  const float factor = std::abs(scale);
  Image image(width, height);
  const char* src = bytes.data() + pos;
  for (int row = 0; row < height; ++row) {
    float* dst = image.rgb.data() + size_t(height - 1 - row) * size_t(width) * 3;
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c, src += 4) {
        uint32_t bits;
        std::memcpy(&bits, src, 4);
        if (swap) bits = byte_swap(bits);
        float v = std::bit_cast<float>(bits);
        if (factor != 1.0f) v *= factor;
        dst[size_t(x) * 3 + size_t(c)] = v;
      }
      if (channels == 1) dst[size_t(x) * 3 + 1] = dst[size_t(x) * 3 + 2] = dst[size_t(x) * 3];
    }
  }
  return image;
}

// ---- OpenEXR (in-memory streams so files go through write_file_atomic / read_file) -------------------------------

class MemoryOStream final : public Imf::OStream {
 public:
  explicit MemoryOStream(const std::string& name) : Imf::OStream(name.c_str()) {}
  void write(const char c[], int n) override {
    const size_t end = pos_ + size_t(n);
    if (end > bytes.size()) bytes.resize(end);
    std::memcpy(bytes.data() + pos_, c, size_t(n));
    pos_ = end;
  }
  uint64_t tellp() override { return pos_; }
  void seekp(uint64_t pos) override { pos_ = size_t(pos); }
  std::string bytes;

 private:
  size_t pos_ = 0;
};

class MemoryIStream final : public Imf::IStream {
 public:
  MemoryIStream(const std::string& name, const std::string& bytes) : Imf::IStream(name.c_str()), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || pos_ > bytes_.size() || bytes_.size() - pos_ < size_t(n))
      throw Iex::InputExc("unexpected end of file");
    std::memcpy(c, bytes_.data() + pos_, size_t(n));
    pos_ += size_t(n);
    return pos_ < bytes_.size();
  }
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override { pos_ = size_t(pos); }

 private:
  const std::string& bytes_;
  size_t pos_ = 0;
};

/// Scanline EXR with 32-bit float R, G, B channels (lossless ZIP compression), values unchanged.
Result<std::string> encode_exr(const std::string& path, const Image& image) {
  try {
    MemoryOStream stream(path);
    {
      Imf::Header header(image.width, image.height);
      header.compression() = Imf::ZIP_COMPRESSION;
      for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      Imf::FrameBuffer frame;
      char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));  // OpenEXR only reads it
      const size_t xstride = 3 * sizeof(float), ystride = xstride * size_t(image.width);
      frame.insert("R", Imf::Slice(Imf::FLOAT, base, xstride, ystride));
      frame.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xstride, ystride));
      frame.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xstride, ystride));
      Imf::OutputFile file(stream, header, 1);
      file.setFrameBuffer(frame);
      file.writePixels(image.height);
    }  // the destructor writes the line offset table
    return std::move(stream.bytes);
  } catch (const std::exception& e) {
    return file_error(path, std::string("OpenEXR: ") + e.what());
  }
}

/// Reads R, G, B (a missing channel reads as 0; a Y-only file becomes grey) over the data window.
Result<Image> decode_exr(const std::string& path, const std::string& bytes) {
  try {
    MemoryIStream stream(path, bytes);
    Imf::InputFile file(stream, 1);
    const Imath::Box2i dw = file.header().dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w > kMaxImageDimension || h > kMaxImageDimension)
      return file_error(path, "EXR data window " + std::to_string(w) + "x" + std::to_string(h) + " out of range");
    const Imf::ChannelList& channels = file.header().channels();
    const char* names[3] = {"R", "G", "B"};
    bool any_rgb = false;
    for (const char* name : names) any_rgb |= channels.findChannel(name) != nullptr;
    const bool grey = !any_rgb && channels.findChannel("Y") != nullptr;
    if (!any_rgb && !grey) return file_error(path, "EXR has no R, G, B or Y channel");
    Image image(static_cast<int>(w), static_cast<int>(h));
    char* base = reinterpret_cast<char*>(image.rgb.data());
    const size_t xstride = 3 * sizeof(float), ystride = xstride * size_t(w);
    Imf::FrameBuffer frame;
    if (grey) {
      frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, base, dw, xstride, ystride));
    } else {
      for (int c = 0; c < 3; ++c)
        frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, base + c * sizeof(float), dw, xstride, ystride));
    }
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
    if (grey)
      for (size_t i = 0; i < image.rgb.size(); i += 3) image.rgb[i + 1] = image.rgb[i + 2] = image.rgb[i];
    return image;
  } catch (const std::exception& e) {
    return file_error(path, std::string("OpenEXR: ") + e.what());
  }
}

// ---- PNG ---------------------------------------------------------------------------------------------------------

void append_to_buffer(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}

/// 8-bit sRGB through the display transform, rounded to nearest, top row first.
Result<std::string> encode_png(const std::string& path, const Image& image, const DisplaySettings& display) {
  std::vector<unsigned char> pixels(image.rgb.size());
  for (size_t i = 0; i < image.rgb.size(); i += 3) {
    const vec3 c = apply_tonemap({image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]}, display);
    for (int k = 0; k < 3; ++k)
      pixels[i + size_t(k)] = static_cast<unsigned char>(std::min(255.0f, srgb_encode(c[k]) * 255.0f + 0.5f));
  }
  std::string out;
  if (stbi_write_png_to_func(append_to_buffer, &out, image.width, image.height, 3, pixels.data(),
                             image.width * 3) == 0)
    return file_error(path, "PNG encoding failed");
  return out;
}

/// Per-channel tonemap of a scaled, non-negative value. Arguments are bounded first so overflow cannot give NaN.
float tonemap_channel(float x, Tonemap tonemap) {
  if (!(x > 0.0f)) return 0.0f;  // negative, zero and NaN
  switch (tonemap) {
    case Tonemap::reinhard:
      x = std::min(x, std::numeric_limits<float>::max());  // inf / inf would be NaN
      return x / (1.0f + x);
    case Tonemap::aces: {
      x = std::min(x, 1.0e4f);  // the fit exceeds 1 beyond x ~ 7.25, so the clamp below is unchanged
      const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
      return std::clamp(y, 0.0f, 1.0f);
    }
    case Tonemap::clamp:
      break;
  }
  return std::min(x, 1.0f);
}

}  // namespace

// Clamp, Reinhard et al. 2002 ("Photographic Tone Reproduction", eq. 3) or Narkowicz 2015 "ACES Filmic Tone Mapping
// Curve" on each channel after scaling by 2^exposure.
vec3 apply_tonemap(vec3 linear, const DisplaySettings& settings) {
  const float scale = std::exp2(settings.exposure);
  return {tonemap_channel(linear.x * scale, settings.tonemap), tonemap_channel(linear.y * scale, settings.tonemap),
          tonemap_channel(linear.z * scale, settings.tonemap)};
}

// IEC 61966-2-1:1999 sRGB encoding: linear segment below 0.0031308, 1.055 x^(1/2.4) - 0.055 above.
float srgb_encode(float linear) {
  if (!(linear > 0.0f)) return 0.0f;
  if (linear >= 1.0f) return 1.0f;
  if (linear <= 0.0031308f) return 12.92f * linear;
  return float(1.055 * std::pow(double(linear), 1.0 / 2.4) - 0.055);
}

std::optional<Error> save_image(const std::string& path, const Image& image, const DisplaySettings& display) {
  const std::string ext = lower_extension(path);
  if (!is_supported_image_extension(path))
    return file_error(path, "unsupported image extension \"" + ext + "\" (expected .png, .pfm or .exr)");
  if (image.width <= 0 || image.height <= 0)
    return file_error(path, "cannot write an empty image (" + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + ")");
  if (image.rgb.size() != size_t(image.width) * size_t(image.height) * 3)
    return file_error(path, "image data has " + std::to_string(image.rgb.size()) + " floats, expected " +
                                std::to_string(size_t(image.width) * size_t(image.height) * 3));
  if (ext == ".pfm") return write_file_atomic(path, encode_pfm(image));
  Result<std::string> bytes = ext == ".png" ? encode_png(path, image, display) : encode_exr(path, image);
  if (!bytes) return Error{bytes.error()};
  return write_file_atomic(path, *bytes);
}

Result<Image> load_image(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (!is_float_image_extension(path))
    return file_error(path, "cannot load \"" + ext + "\" images (expected .pfm or .exr)");
  Result<std::string> bytes = read_whole_file(path, std::numeric_limits<uint64_t>::max());
  if (!bytes) return Error{bytes.error()};
  return ext == ".pfm" ? decode_pfm(path, *bytes) : decode_exr(path, *bytes);
}

bool is_supported_image_extension(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".png" || is_float_image_extension(path);
}

bool is_float_image_extension(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".pfm" || ext == ".exr";
}

}  // namespace pt
