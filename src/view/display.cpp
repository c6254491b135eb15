#include "view/display.h"

#include <glad/gl.h>
#include <stb_image_write.h>

#include <cstring>
#include <vector>

#include "core/atomic_file.h"
#include "shaders.h"

namespace pt {

namespace {

std::string compile(unsigned type, const char* src, unsigned& out) {
  out = glCreateShader(type);
  glShaderSource(out, 1, &src, nullptr);
  glCompileShader(out);
  int ok = 0;
  glGetShaderiv(out, GL_COMPILE_STATUS, &ok);
  if (ok) return {};
  char log[1024] = "";
  glGetShaderInfoLog(out, sizeof log, nullptr, log);
  return std::string("shader compile failed: ") + log;
}

}  // namespace

std::string GlDisplay::init() {
  unsigned vs = 0, fs = 0;
  if (std::string e = compile(GL_VERTEX_SHADER, shaders::display_vert, vs); !e.empty()) return e;
  if (std::string e = compile(GL_FRAGMENT_SHADER, shaders::display_frag, fs); !e.empty()) return e;
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  int ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) return "shader link failed";
  loc_exposure_ = glGetUniformLocation(program_, "u_exposure");
  loc_tonemap_ = glGetUniformLocation(program_, "u_tonemap");
  loc_image_ = glGetUniformLocation(program_, "u_image");
  glGenVertexArrays(1, &vao_);
  glGenTextures(1, &texture_);
  glGenBuffers(1, &pbo_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return {};
}

void GlDisplay::destroy() {
  if (texture_) glDeleteTextures(1, &texture_);
  if (pbo_) glDeleteBuffers(1, &pbo_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (program_) glDeleteProgram(program_);
  texture_ = vao_ = program_ = pbo_ = 0;
}

void GlDisplay::upload(const Image& image) {
  if (image.width <= 0 || image.height <= 0) return;
  // Through a pixel buffer object: the copy into the PBO is a memcpy into driver memory, and the texture update
  // from it is asynchronous, so a large window does not stall the UI thread on the transfer (orphaning the buffer
  // each time lets the driver keep the previous one in flight).
  const size_t bytes = image.rgb.size() * sizeof(float);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo_);
  glBufferData(GL_PIXEL_UNPACK_BUFFER, GLsizeiptr(bytes), nullptr, GL_STREAM_DRAW);
  if (void* dst = glMapBufferRange(GL_PIXEL_UNPACK_BUFFER, 0, GLsizeiptr(bytes),
                                   GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT)) {
    std::memcpy(dst, image.rgb.data(), bytes);
    glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER);
  } else {
    glBufferSubData(GL_PIXEL_UNPACK_BUFFER, 0, GLsizeiptr(bytes), image.rgb.data());
  }
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  if (image.width != tex_w_ || image.height != tex_h_) {
    tex_w_ = image.width;
    tex_h_ = image.height;
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, tex_w_, tex_h_, 0, GL_RGB, GL_FLOAT, nullptr);
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, tex_w_, tex_h_, GL_RGB, GL_FLOAT, nullptr);
  }
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
}

void GlDisplay::draw(int x, int y, int w, int h, const DisplaySettings& display) const {
  if (tex_w_ == 0) return;
  glViewport(x, y, w, h);
  glUseProgram(program_);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glUniform1i(loc_image_, 0);
  glUniform1f(loc_exposure_, display.exposure);
  glUniform1i(loc_tonemap_, int(display.tonemap));
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
}

Rect letterbox(int area_w, int area_h, int image_w, int image_h) {
  Rect r;
  if (area_w <= 0 || area_h <= 0 || image_w <= 0 || image_h <= 0) return r;
  double scale = std::min(double(area_w) / image_w, double(area_h) / image_h);
  r.w = std::max(1, int(image_w * scale));
  r.h = std::max(1, int(image_h * scale));
  r.x = (area_w - r.w) / 2;
  r.y = (area_h - r.h) / 2;
  return r;
}

std::optional<Error> save_framebuffer_png(const std::string& path, int w, int h) {
  std::vector<unsigned char> pixels(size_t(w) * size_t(h) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // GL rows go bottom to top; PNG rows top to bottom.
  std::vector<unsigned char> flipped(pixels.size());
  for (int y = 0; y < h; ++y)
    std::copy_n(&pixels[size_t(h - 1 - y) * w * 3], size_t(w) * 3, &flipped[size_t(y) * w * 3]);
  std::string bytes;
  auto sink = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), size_t(size));
  };
  if (!stbi_write_png_to_func(sink, &bytes, w, h, 3, flipped.data(), w * 3))
    return Error{path + ": PNG encoding failed"};
  return write_file_atomic(path, bytes);
}

}  // namespace pt
