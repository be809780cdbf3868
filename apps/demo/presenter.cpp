#include "apps/demo/presenter.h"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "shared/pip.h"

namespace penumbra::demo {
namespace {

// A triangle covering the viewport; no vertex buffer.
constexpr const char* kVertexShader = R"(#version 330 core
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";

// texelFetch of the texel under the fragment: exact nearest sampling, so at scale 1 the
// framebuffer holds the frame's bytes unchanged. Texture row 0 is the frame's top row.
constexpr const char* kFragmentShaderTemplate = R"(#version 330 core
uniform sampler2D image;
uniform usampler2D pip;
uniform sampler2D errorMap;
uniform usampler2D tiles;  // PIP_TILE_* per PIP_MASK_TILE_SIZE^2 tile
uniform int overlay;   // 0 none, 1 PIP, 2 penumbra mask, 3 thin, 4 error, 5 tiles
uniform vec2 origin;   // viewport origin in window pixels
uniform float scale;   // window pixels per texel
uniform ivec2 size;    // frame size in texels
out vec4 colour;

vec3 tint(vec3 c, vec3 t) { return 0.35 * c + 0.65 * t; }

void main() {
  ivec2 t = ivec2(floor((gl_FragCoord.xy - origin) / scale));
  t = clamp(t, ivec2(0), size - 1);
  t.y = size.y - 1 - t.y;
  vec3 c = texelFetch(image, t, 0).rgb;
  uint flags = texelFetch(pip, t, 0).r;
  if (overlay == 1 && flags != 0u) c = tint(c, vec3(1.0, 0.0, 0.0));  // traced pixels red, as srt.pip.png (Fig. 4)
  if (overlay == 2 && (flags & PIP_PENUMBRA) != 0u) c = tint(c, vec3(1.0, 0.75, 0.0));
  if (overlay == 3 && (flags & PIP_THIN) != 0u) c = tint(c, vec3(0.0, 0.9, 1.0));
  if (overlay == 4) c = texelFetch(errorMap, t, 0).rgb;
  uint verdict = texelFetch(tiles, t / PIP_MASK_TILE_SIZE, 0).r;  // as srt.pip.png (hybrid/frame_output.cpp)
  if (overlay == 5 && flags != 0u) c = tint(c, verdict == PIP_TILE_TRACE ? vec3(1.0, 0.6, 0.0) : vec3(1.0, 0.0, 0.0));
  if (overlay == 5 && flags == 0u && verdict == PIP_TILE_CLEAR) c = tint(c, vec3(0.25, 0.5, 1.0));
  colour = vec4(c, 1.0);
}
)";

unsigned compile(GLenum stage, const std::string& source) {
  const unsigned shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error(std::string("presenter shader does not compile: ") + log);
  }
  return shader;
}

unsigned makeTexture() {
  unsigned texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return texture;
}

}  // namespace

Presenter::Presenter() {
  // The PIP bit values come from the shared header, so the overlay cannot drift from the passes.
  const std::string defines =
      "#define PIP_THIN " + std::to_string(PIP_THIN) + "u\n#define PIP_PENUMBRA " + std::to_string(PIP_PENUMBRA) +
      "u\n#define PIP_TILE_CLEAR " + std::to_string(PIP_TILE_CLEAR) + "u\n#define PIP_TILE_TRACE " +
      std::to_string(PIP_TILE_TRACE) + "u\n#define PIP_MASK_TILE_SIZE " + std::to_string(PIP_MASK_TILE_SIZE) + "\n";
  std::string fragment = kFragmentShaderTemplate;
  fragment.insert(fragment.find('\n') + 1, defines);
  const unsigned vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const unsigned fs = compile(GL_FRAGMENT_SHADER, fragment);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program_, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("presenter shader does not link: ") + log);
  }
  glUseProgram(program_);
  glUniform1i(glGetUniformLocation(program_, "image"), 0);
  glUniform1i(glGetUniformLocation(program_, "pip"), 1);
  glUniform1i(glGetUniformLocation(program_, "errorMap"), 2);
  glUniform1i(glGetUniformLocation(program_, "tiles"), 3);
  overlayLocation_ = glGetUniformLocation(program_, "overlay");
  originLocation_ = glGetUniformLocation(program_, "origin");
  scaleLocation_ = glGetUniformLocation(program_, "scale");
  sizeLocation_ = glGetUniformLocation(program_, "size");
  glGenVertexArrays(1, &vertexArray_);  // core profile draws need one bound, even empty
  image_ = makeTexture();
  pip_ = makeTexture();
  error_ = makeTexture();
  tiles_ = makeTexture();
}

Presenter::~Presenter() {
  const unsigned textures[] = {image_, pip_, error_, tiles_};
  glDeleteTextures(4, textures);
  glDeleteVertexArrays(1, &vertexArray_);
  glDeleteProgram(program_);
}

void Presenter::allocate(std::uint32_t width, std::uint32_t height) {
  width_ = width;
  height_ = height;
  glBindTexture(GL_TEXTURE_2D, image_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, GLsizei(width), GLsizei(height), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glBindTexture(GL_TEXTURE_2D, error_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, GLsizei(width), GLsizei(height), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glBindTexture(GL_TEXTURE_2D, pip_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8UI, GLsizei(width), GLsizei(height), 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
  glBindTexture(GL_TEXTURE_2D, tiles_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8UI, GLsizei(tileColumns()), GLsizei(tileRows()), 0, GL_RED_INTEGER,
               GL_UNSIGNED_BYTE, nullptr);
  zeros_.assign(std::size_t(width) * height, 0);
}

void Presenter::upload(const Frame& frame, std::span<const std::uint8_t> pipFlags,
                       std::span<const std::uint8_t> errorHeatmap, std::span<const std::uint8_t> maskTiles) {
  const std::size_t pixels = std::size_t(frame.width) * frame.height;
  if (frame.rgba.size() != pixels * 4) throw std::logic_error("Presenter::upload: frame has no RGBA image");
  if (frame.width != width_ || frame.height != height_) allocate(frame.width, frame.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // R8UI rows of odd widths are not 4-byte aligned
  glBindTexture(GL_TEXTURE_2D, image_);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, GLsizei(width_), GLsizei(height_), GL_RGBA, GL_UNSIGNED_BYTE, frame.rgba.data());
  glBindTexture(GL_TEXTURE_2D, pip_);
  const std::uint8_t* flags = pipFlags.size() == pixels ? pipFlags.data() : zeros_.data();
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, GLsizei(width_), GLsizei(height_), GL_RED_INTEGER, GL_UNSIGNED_BYTE, flags);
  glBindTexture(GL_TEXTURE_2D, tiles_);
  const std::uint8_t* tiles =
      maskTiles.size() == std::size_t(tileColumns()) * tileRows() ? maskTiles.data() : zeros_.data();
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, GLsizei(tileColumns()), GLsizei(tileRows()), GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                  tiles);
  hasError_ = errorHeatmap.size() == pixels * 4;
  if (hasError_) {
    glBindTexture(GL_TEXTURE_2D, error_);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, GLsizei(width_), GLsizei(height_), GL_RGBA, GL_UNSIGNED_BYTE,
                    errorHeatmap.data());
  }
}

void Presenter::draw(int framebufferWidth, int framebufferHeight, Overlay overlay) {
  glViewport(0, 0, framebufferWidth, framebufferHeight);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
  glClearColor(0.12f, 0.12f, 0.13f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (width_ == 0 || framebufferWidth <= 0 || framebufferHeight <= 0) return;
  // Whole-texel magnification when the frame fits (crisp, every texel the same size), else shrink.
  float scale = std::min(float(framebufferWidth) / float(width_), float(framebufferHeight) / float(height_));
  if (scale >= 1.0f) scale = std::floor(scale);
  const int w = std::max(1, int(std::lround(scale * float(width_))));
  const int h = std::max(1, int(std::lround(scale * float(height_))));
  viewport_[0] = (framebufferWidth - w) / 2;
  viewport_[1] = (framebufferHeight - h) / 2;
  viewport_[2] = w;
  viewport_[3] = h;
  glViewport(viewport_[0], viewport_[1], w, h);
  glUseProgram(program_);
  glUniform1i(overlayLocation_, overlay == Overlay::Error && !hasError_ ? 0 : int(overlay));
  glUniform2f(originLocation_, float(viewport_[0]), float(viewport_[1]));
  glUniform1f(scaleLocation_, scale);
  glUniform2i(sizeLocation_, int(width_), int(height_));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, image_);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, pip_);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, error_);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, tiles_);
  glActiveTexture(GL_TEXTURE0);
  glBindVertexArray(vertexArray_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glViewport(0, 0, framebufferWidth, framebufferHeight);
}

Presenter::Image Presenter::screenshot() const {
  const int w = viewport_[2], h = viewport_[3];
  std::vector<std::uint8_t> bottomUp(std::size_t(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(viewport_[0], viewport_[1], w, h, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
  Image image{w, h, std::vector<std::uint8_t>(bottomUp.size())};
  const std::size_t row = std::size_t(w) * 4;
  for (int y = 0; y < h; ++y) {
    std::copy_n(bottomUp.data() + std::size_t(h - 1 - y) * row, row, image.rgba.data() + std::size_t(y) * row);
  }
  return image;
}

}  // namespace penumbra::demo
