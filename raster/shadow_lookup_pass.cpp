#include "raster/shadow_lookup_pass.h"

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

void ShadowLookupPass::record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const ShadowMapPass& shadowMap,
                              const gpu::Buffer& frame, const gpu::Buffer& visibility, float accumulateWeight) const {
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
  cmd.dispatch((gbuffer.width() + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE,
               (gbuffer.height() + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra::raster
