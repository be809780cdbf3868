// The scene's triangles uploaded once for rasterization: one interleaved vertex buffer and one
// index buffer in scene order, so a raster pass draws the whole scene with a single indexed draw.
// Passes that cut alpha-tested meshes (core/cutouts.h) draw the opaque meshes so, then each cut-out
// mesh with its texture coordinates (a second vertex buffer) and its cut-out in push constants.
// The camera pass draws the meshes with a colour texture each on its own too (drawTextured).
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "core/cutouts.h"
#include "core/scene.h"
#include "gpu/pipeline.h"
#include "gpu/resources.h"
#include "shared/raster.h"

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

// The vertex input of the cut-out draws: readPositions or the camera pass's attributes, plus the
// texture coordinate at location 4 from binding 1.
inline void readTextureCoordinates(gpu::GraphicsPipelineDesc& d) {
  d.vertexBindings.push_back({.binding = 1, .stride = sizeof(glm::vec2), .inputRate = vk::VertexInputRate::eVertex});
  d.vertexAttributes.push_back({4, 1, vk::Format::eR32G32Sfloat, 0});
}

static_assert(sizeof(shared::CutoutDrawPush) == 112, "CutoutDrawPush must match std430");

// One opaque mesh's draw with its colour texture (Mesh::colorTexture).
struct TexturedDraw {
  std::uint32_t firstIndex = 0, indexCount = 0;
  std::int32_t colorTexture = -1;
};

// One cut-out mesh's draw: its indices, colour texture and its cut-out as CutoutDrawPush takes it.
struct CutoutDraw {
  std::uint32_t firstIndex = 0, indexCount = 0;
  std::int32_t colorTexture = -1;
  std::uint32_t firstTriangle = 0;  // its first triangle's CutoutTriangle (core/cutouts.h)
  std::uint32_t firstTexel = 0, width = 0, height = 0;
  float factor = 1.0f, cutoff = 0.5f;
};

class SceneGeometry {
 public:
  SceneGeometry(const gpu::Context& context, const Scene& scene);
  // Rewrites the vertices of the scene's dynamic meshes (same scene, posed anew; host-visible
  // memory, so call it between frames, when no submission reads the buffer).
  void update(const Scene& scene);
  // Counts update()s: passes that cache what they derived from the vertices compare it.
  std::uint64_t version() const { return version_; }
  void bind(const vk::raii::CommandBuffer& cmd) const;  // vertex + index buffers
  void draw(const vk::raii::CommandBuffer& cmd) const;  // the whole scene, cut-outs drawn solid
  void drawOpaque(const vk::raii::CommandBuffer& cmd) const;  // every mesh that is not cut out
  void drawPlain(const vk::raii::CommandBuffer& cmd) const;   // ... and has no colour texture
  // Each opaque mesh with a colour texture: binds the texture coordinates, lets `push` set what the
  // draw needs, then draws it.
  void drawTextured(const vk::raii::CommandBuffer& cmd, const std::function<void(const TexturedDraw&)>& push) const;
  bool hasCutouts() const { return !cutouts_.empty(); }
  // Each cut-out mesh: binds the texture coordinates, lets `push` set the push constants (from
  // cutoutPush), then draws it. Bind the cut-out pipeline first.
  void drawCutouts(const vk::raii::CommandBuffer& cmd, const std::function<void(const CutoutDraw&)>& push) const;
  // A cut-out draw's push constants in a pass with matrix `viewProj` (and the camera pass's position).
  shared::CutoutDrawPush cutoutPush(const glm::mat4& viewProj, const glm::vec4& camera, const CutoutDraw& draw) const;
  // The addresses of the CutoutTriangles and of the alpha words (core/cutouts.h), as (low, high).
  glm::uvec2 cutoutTrianglesAddress() const;
  glm::uvec2 cutoutTexelsAddress() const;
  std::uint32_t indexCount() const { return indexCount_; }
  vk::DeviceSize bytes() const {
    return vertices_.size() + indices_.size() + uvs_.size() + triangles_.size() + texels_.size();
  }
  // Also bound as storage buffers (RasterVertex as 9 floats; 3 indices per triangle) by compute passes.
  const gpu::Buffer& vertices() const { return vertices_; }
  const gpu::Buffer& indices() const { return indices_; }

 private:
  SceneGeometry(const gpu::Context& context, const Scene& scene, const CutoutData& cutouts);
  gpu::Buffer vertices_;
  gpu::Buffer indices_;
  gpu::Buffer uvs_;        // a texture coordinate per vertex (zero for meshes without); a word without any
  gpu::Buffer triangles_;  // the CutoutTriangles and ...
  gpu::Buffer texels_;     // ... the cut-out textures' alpha (core/cutouts.h), read through their addresses
  std::uint32_t indexCount_ = 0;
  // First index and count of each run of opaque meshes, and of those of them without a colour texture.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> opaque_, plain_;
  std::vector<TexturedDraw> textured_;
  std::vector<CutoutDraw> cutouts_;
  std::uint64_t version_ = 0;
};

}  // namespace penumbra::raster
