#include "raster/depth_pyramid_pass.h"

#include "depth_pyramid_comp.h"

namespace penumbra::raster {
namespace {

constexpr gpu::Binding kBindings[] = {{PYRAMID_BINDING_SHADOW_MAP, vk::DescriptorType::eCombinedImageSampler},
                                      {PYRAMID_BINDING_THIN_MASK, vk::DescriptorType::eCombinedImageSampler},
                                      {PYRAMID_BINDING_TILES, vk::DescriptorType::eStorageBuffer},
                                      {PYRAMID_BINDING_SHADOW_TEXELS, vk::DescriptorType::eStorageBuffer},
                                      {PYRAMID_BINDING_THIN_TEXELS, vk::DescriptorType::eStorageBuffer}};

static_assert(sizeof(shared::PyramidPush) == 48, "PyramidPush must match std430 in shared/pyramid.h");

// Levels until one tile covers the whole face.
std::uint32_t levelCount(std::uint32_t resolution) {
  std::uint32_t levels = 1;
  while (shared::pyramidDim(resolution, levels) > 1 && levels < PYRAMID_MAX_LEVELS - 1) ++levels;
  return levels;
}

vk::DeviceSize tileBytes(std::uint32_t resolution, std::uint32_t faceCount) {
  const std::uint32_t levels = levelCount(resolution);
  // two channels per tile, then a fit per tile of level >= 2
  return vk::DeviceSize(shared::pyramidFitIndex(resolution, faceCount, levels, levels + 1, 0)) * sizeof(float);
}

}  // namespace

DepthPyramidPass::DepthPyramidPass(const gpu::Context& context, std::uint32_t resolution, std::uint32_t faceCount)
    : resolution_(resolution),
      faceCount_(faceCount),
      levels_(levelCount(resolution)),
      tiles_(context, tileBytes(resolution, faceCount), vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eShaderDeviceAddress, "depth pyramid"),
      pipeline_(context, depth_pyramid_comp, kBindings, sizeof(shared::PyramidPush), "depth pyramid pipeline") {}

void DepthPyramidPass::record(const vk::raii::CommandBuffer& cmd, const ShadowMapPass& shadowMap, const ThinTrianglePass* thin,
                              const shared::ShadowMapInfo& info, float deltaThreshold) const {
  // Without a thin mask the bindings still need an image and a buffer: the shadow map's stand in, unread.
  const gpu::ComputePipeline& pipeline = pipeline_(texelReads(shadowMap, thin));
  pipeline.bind(cmd,
                gpu::Descriptors{}
                    .sampledImage(PYRAMID_BINDING_SHADOW_MAP, shadowMap.depth().view(), shadowMap.sampler())
                    .sampledImage(PYRAMID_BINDING_THIN_MASK, thin ? thin->depth().view() : shadowMap.depth().view(),
                                  thin ? thin->sampler() : shadowMap.sampler())
                    .buffer(PYRAMID_BINDING_TILES, tiles_)
                    .buffer(PYRAMID_BINDING_SHADOW_TEXELS, shadowMap.texels())
                    .buffer(PYRAMID_BINDING_THIN_TEXELS, thin ? thin->texels() : shadowMap.texels()));
  for (std::uint32_t level = 1; level <= levels_; ++level) {
    pipeline.pushConstants(cmd, shared::PyramidPush{.level = level,
                                                    .resolution = resolution_,
                                                    .faceCount = faceCount_,
                                                    .useThin = thin ? 1u : 0u,
                                                    .kind = info.kind,
                                                    .nearPlane = info.nearPlane,
                                                    .farPlane = info.farPlane,
                                                    .deltaThreshold = deltaThreshold,
                                                    .levels = levels_});
    const std::uint32_t dim = shared::pyramidDim(resolution_, level);
    cmd.dispatch((dim + PYRAMID_GROUP_SIZE - 1) / PYRAMID_GROUP_SIZE, (dim + PYRAMID_GROUP_SIZE - 1) / PYRAMID_GROUP_SIZE, faceCount_);
    gpu::computeToComputeAndHost(cmd);
  }
}

}  // namespace penumbra::raster
