// Camera pass: rasterizes the scene into a G-buffer (world position + coverage, normal, albedo,
// face normal; shared/gbuffer.h). The albedo is the base colour times the colour texture's, whose
// images the pass owns (ColorTextures).
// After record() the colour attachments are in GENERAL layout, readable by compute passes and copies.
#pragma once
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/camera.h"
#include "gpu/pipeline.h"
#include "raster/color_textures.h"
#include "raster/scene_geometry.h"

namespace penumbra::raster {

class GBufferPass {
 public:
  GBufferPass(const gpu::Context& context, const Scene& scene, std::uint32_t width, std::uint32_t height);
  void record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const ViewMatrices& view,
              const glm::vec3& cameraPosition) const;
  // Copies position and normal to host-visible memory (record after record()).
  void recordReadback(const vk::raii::CommandBuffer& cmd) const;
  std::vector<glm::vec4> positions() const;  // after the readback completed; w = coverage
  std::vector<glm::vec4> normals() const;

  const gpu::Image& position() const { return position_; }
  const gpu::Image& normal() const { return normal_; }
  const gpu::Image& albedo() const { return albedo_; }
  const gpu::Image& faceNormal() const { return faceNormal_; }
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  vk::DeviceSize bytes() const {
    return position_.bytes() + normal_.bytes() + albedo_.bytes() + faceNormal_.bytes() + depth_.bytes() +
           textures_.bytes();
  }

 private:
  std::uint32_t width_, height_;
  gpu::Image position_, normal_, albedo_, faceNormal_, depth_;
  gpu::Buffer positionReadback_, normalReadback_;
  ColorTextures textures_;
  gpu::GraphicsPipeline pipeline_;
  gpu::GraphicsPipeline texturedPipeline_;  // opaque meshes with a colour texture
  gpu::GraphicsPipeline cutoutPipeline_;    // cut-out meshes: nothing where their texture cuts them away
};

}  // namespace penumbra::raster
