// Edge pyramid of a light's faces (see shaders/shared/pyramid.h), so that classification can ask
// "the nearest edge texel within R texels?" with a handful of reads whatever R is (penumbra mask).
#pragma once
#include "gpu/pipeline.h"
#include "raster/shadow_map_pass.h"
#include "raster/thin_triangle_pass.h"
#include "shared/pyramid.h"

namespace penumbra::raster {

class DepthPyramidPass {
 public:
  DepthPyramidPass(const gpu::Context& context, std::uint32_t resolution, std::uint32_t faceCount);
  // thin may be nullptr (no thin-triangle pass): then the minimum is the shadow map's alone.
  void record(const vk::raii::CommandBuffer& cmd, const ShadowMapPass& shadowMap, const ThinTrianglePass* thin,
              const shared::ShadowMapInfo& info, float deltaThreshold) const;
  const gpu::Buffer& tiles() const { return tiles_; }
  std::uint32_t levels() const { return levels_; }
  std::uint32_t faceCount() const { return faceCount_; }
  std::uint32_t resolution() const { return resolution_; }

 private:
  std::uint32_t resolution_, faceCount_, levels_;
  gpu::Buffer tiles_;
  gpu::SpecializedComputePipeline pipeline_;  // on texelReads()
};

}  // namespace penumbra::raster
