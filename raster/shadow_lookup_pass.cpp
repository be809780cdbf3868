#include "raster/shadow_lookup_pass.h"

#include <algorithm>

#include "shadow_lookup_comp.h"
#include "shared/raster.h"

namespace penumbra::raster {
namespace {

constexpr gpu::Binding kBindings[] = {{LOOKUP_BINDING_POSITION, vk::DescriptorType::eStorageImage},
                                      {LOOKUP_BINDING_NORMAL, vk::DescriptorType::eStorageImage},
                                      {LOOKUP_BINDING_SHADOW_MAP, vk::DescriptorType::eCombinedImageSampler},
                                      {LOOKUP_BINDING_FRAME, vk::DescriptorType::eStorageBuffer},
                                      {LOOKUP_BINDING_VISIBILITY, vk::DescriptorType::eStorageBuffer},
                                      {LOOKUP_BINDING_SHADOW_TEXELS, vk::DescriptorType::eStorageBuffer},
                                      {LOOKUP_BINDING_FACE_NORMAL, vk::DescriptorType::eStorageImage}};

// Matches the shader's push block.
struct LookupPush {
  float accumulateWeight;
};

}  // namespace

ShadowLookupPass::ShadowLookupPass(const gpu::Context& context)
    : pipeline_(context, shadow_lookup_comp, kBindings, sizeof(LookupPush), "shadow lookup pipeline") {}

void ShadowLookupPass::record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer,
                              const ShadowMapPass& shadowMap, const gpu::Buffer& frame, const gpu::Buffer& visibility,
                              glm::uvec4 lightRect, float accumulateWeight) const {
  if (lightRect != glm::uvec4(0u, 0u, gbuffer.width(), gbuffer.height()) && accumulateWeight == 0.0f) {
    cmd.fillBuffer(visibility.handle(), 0, VK_WHOLE_SIZE, 0u);  // 0.0f beyond the rectangle
    gpu::memoryBarrier(cmd, vk::PipelineStageFlagBits2::eAllTransfer, vk::AccessFlagBits2::eTransferWrite,
                       vk::PipelineStageFlagBits2::eComputeShader,
                       vk::AccessFlagBits2::eShaderStorageRead | vk::AccessFlagBits2::eShaderStorageWrite);
  }
  const gpu::ComputePipeline& pipeline = pipeline_(shadowMap.hasTexelCopy());
  pipeline.bind(cmd, gpu::Descriptors{}
                         .storageImage(LOOKUP_BINDING_POSITION, gbuffer.position().view())
                         .storageImage(LOOKUP_BINDING_NORMAL, gbuffer.normal().view())
                         .sampledImage(LOOKUP_BINDING_SHADOW_MAP, shadowMap.depth().view(), shadowMap.sampler())
                         .buffer(LOOKUP_BINDING_FRAME, frame)
                         .buffer(LOOKUP_BINDING_VISIBILITY, visibility)
                         .buffer(LOOKUP_BINDING_SHADOW_TEXELS, shadowMap.texels())
                         .storageImage(LOOKUP_BINDING_FACE_NORMAL, gbuffer.faceNormal().view()));
  pipeline.pushConstants(cmd, LookupPush{accumulateWeight});
  const glm::uvec2 size(lightRect.z - std::min(lightRect.x, lightRect.z),
                        lightRect.w - std::min(lightRect.y, lightRect.w));
  if (size.x > 0u && size.y > 0u) {
    cmd.dispatch((size.x + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE,
                 (size.y + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE, 1);
  }
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra::raster
