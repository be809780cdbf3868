// The scene's triangles uploaded once for rasterization: one interleaved vertex buffer and one
// index buffer, so every raster pass draws the whole scene with a single indexed draw.
#pragma once
#include <cstdint>

#include <glm/glm.hpp>

#include "core/scene.h"
#include "gpu/pipeline.h"
#include "gpu/resources.h"

namespace penumbra::raster {

struct RasterVertex {  // vertex attributes (locations 0, 1, 2)
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec3 color;
};
static_assert(sizeof(RasterVertex) == 36);

// The vertex input of passes that read positions only (location 0): light and caster passes.
inline void readPositions(gpu::GraphicsPipelineDesc& d) {
  d.vertexBindings = {{.binding = 0, .stride = sizeof(RasterVertex), .inputRate = vk::VertexInputRate::eVertex}};
  d.vertexAttributes = {{0, 0, vk::Format::eR32G32B32Sfloat, offsetof(RasterVertex, position)}};
}

class SceneGeometry {
 public:
  SceneGeometry(const gpu::Context& context, const Scene& scene);
  // Rewrites the vertices of the scene's dynamic meshes (same scene, posed anew; host-visible
  // memory, so call it between frames, when no submission reads the buffer).
  void update(const Scene& scene);
  // Counts update()s: passes that cache what they derived from the vertices compare it.
  std::uint64_t version() const { return version_; }
  void bind(const vk::raii::CommandBuffer& cmd) const;  // vertex + index buffers
  void draw(const vk::raii::CommandBuffer& cmd) const;  // the whole scene
  std::uint32_t indexCount() const { return indexCount_; }
  vk::DeviceSize bytes() const { return vertices_.size() + indices_.size(); }
  // Also bound as storage buffers (RasterVertex as 9 floats; 3 indices per triangle) by compute passes.
  const gpu::Buffer& vertices() const { return vertices_; }
  const gpu::Buffer& indices() const { return indices_; }

 private:
  gpu::Buffer vertices_;
  gpu::Buffer indices_;
  std::uint32_t indexCount_ = 0;
  std::uint64_t version_ = 0;
};

}  // namespace penumbra::raster
