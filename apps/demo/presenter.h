// The presentation path, kept apart from everything else: the frame Penumbra rendered with Vulkan
// is copied to the host (Renderer::render reads it back) and uploaded into OpenGL textures every
// frame with glTexSubImage2D, then drawn by one fullscreen GL shader that also composes the
// overlays. On lavapipe the frame lives in host memory anyway. On a real GPU, sharing the Vulkan
// images with GL (VK_KHR_external_memory_fd + GL_EXT_memory_object_fd, with a shared semaphore via
// GL_EXT_semaphore_fd) would replace upload() and leave draw() and screenshot() as they are.
//
// Needs a current OpenGL 3.3 core context.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "apps/demo/overlay.h"
#include "hybrid/renderer.h"
#include "shared/pip.h"

namespace penumbra::demo {

class Presenter {
 public:
  Presenter();  // compiles the shader; std::runtime_error with the GL log if it fails
  ~Presenter();
  Presenter(const Presenter&) = delete;
  Presenter& operator=(const Presenter&) = delete;

  // Uploads the frame's RGBA8 image and PIP flags (zeros when the method does not classify) and,
  // when given, the error heatmap (width*height*4 bytes) and the tile test's verdicts
  // (Frame::maskTiles).
  void upload(const Frame& frame, std::span<const std::uint8_t> pipFlags,
              std::span<const std::uint8_t> errorHeatmap = {}, std::span<const std::uint8_t> maskTiles = {});
  // Clears the framebuffer and draws the frame with `overlay`, scaled by whole texels where it
  // fits and otherwise by the largest factor that keeps the aspect, centred, nearest sampling.
  // Overlay::Error without an uploaded heatmap draws the plain image.
  void draw(int framebufferWidth, int framebufferHeight, Overlay overlay);
  // The presented frame as drawn by draw() (call it before the UI is drawn over it): the pixels of
  // the frame's rectangle read back with glReadPixels, RGBA8, row 0 at the top.
  struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
  };
  Image screenshot() const;
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }

 private:
  void allocate(std::uint32_t width, std::uint32_t height);
  std::uint32_t tileColumns() const { return (width_ + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE; }
  std::uint32_t tileRows() const { return (height_ + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE; }

  unsigned program_ = 0, vertexArray_ = 0;
  unsigned image_ = 0, pip_ = 0, error_ = 0, tiles_ = 0;  // textures
  int overlayLocation_ = -1, originLocation_ = -1, scaleLocation_ = -1, sizeLocation_ = -1;
  std::uint32_t width_ = 0, height_ = 0;
  bool hasError_ = false;
  int viewport_[4] = {0, 0, 0, 0};  // where the last draw() put the frame
  std::vector<std::uint8_t> zeros_;
};

}  // namespace penumbra::demo
