#include "raster/shadow_lookup_pass.h"

#include "shadow_lookup_comp.h"
#include "shared/raster.h"

namespace penumbra::raster {
namespace {

constexpr gpu::Binding kBindings[] = {{0, vk::DescriptorType::eStorageImage},
                                      {1, vk::DescriptorType::eStorageImage},
                                      {2, vk::DescriptorType::eCombinedImageSampler},
                                      {3, vk::DescriptorType::eStorageBuffer},
                                      {4, vk::DescriptorType::eStorageBuffer},
                                      {5, vk::DescriptorType::eStorageBuffer},
                                      {6, vk::DescriptorType::eStorageImage}};

// Matches the shader's push block.
struct LookupPush {
  float accumulateWeight;
};

}  // namespace

ShadowLookupPass::ShadowLookupPass(const gpu::Context& context)
    : pipeline_(context, shadow_lookup_comp, kBindings, sizeof(LookupPush), "shadow lookup pipeline") {}

void ShadowLookupPass::record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const ShadowMapPass& shadowMap,
                              const gpu::Buffer& frame, const gpu::Buffer& visibility, float accumulateWeight) const {
  const gpu::ComputePipeline& pipeline = pipeline_(shadowMap.hasTexelCopy());
  pipeline.bind(cmd, gpu::Descriptors{}
                         .storageImage(0, gbuffer.position().view())
                         .storageImage(1, gbuffer.normal().view())
                         .sampledImage(2, shadowMap.depth().view(), shadowMap.sampler())
                         .buffer(3, frame)
                         .buffer(4, visibility)
                         .buffer(5, shadowMap.texels())
                         .storageImage(6, gbuffer.faceNormal().view()));
  pipeline.pushConstants(cmd, LookupPush{accumulateWeight});
  cmd.dispatch((gbuffer.width() + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE,
               (gbuffer.height() + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra::raster
