#include "raster/pip_classify_pass.h"

#include <algorithm>

#include "pip_classify_comp.h"

namespace penumbra::raster {
namespace {

constexpr gpu::Binding kBindings[] = {{0, vk::DescriptorType::eStorageImage},         {1, vk::DescriptorType::eStorageImage},
                                      {2, vk::DescriptorType::eCombinedImageSampler}, {3, vk::DescriptorType::eCombinedImageSampler},
                                      {4, vk::DescriptorType::eStorageBuffer},        {5, vk::DescriptorType::eStorageBuffer},
                                      {6, vk::DescriptorType::eStorageBuffer},        {7, vk::DescriptorType::eStorageBuffer},
                                      {8, vk::DescriptorType::eStorageBuffer},        {13, vk::DescriptorType::eStorageBuffer},
                                      {14, vk::DescriptorType::eStorageBuffer},       {15, vk::DescriptorType::eStorageImage}};

}  // namespace

PipClassifyPass::PipClassifyPass(const gpu::Context& context)
    : pipeline_(context, pip_classify_comp, kBindings, sizeof(shared::PipPush), "pip classify pipeline") {}

shared::PipPush PipClassifyPass::pushFor(const PipSettings& settings, const shared::ShadowMapInfo& info, bool thinMaskBound,
                                         float sceneRadius) {
  shared::PipPush push{};
  push.deltaThreshold = settings.deltaFraction * (info.farPlane - info.nearPlane);
  // A texel's world size at the scene's far side bounds the depth error of one texel.
  const float texel = info.kind == SHADOW_ORTHO ? info.texelWorld : info.texelWorld * info.farPlane;
  push.depthMargin = settings.marginTexels * std::min(texel, sceneRadius);
  push.useThin = thinMaskBound ? 1u : 0u;
  push.useIntervals = settings.rayIntervals ? 1u : 0u;
  push.explain = settings.explain ? 1u : 0u;
  return push;
}

void PipClassifyPass::record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const ShadowMapPass& shadowMap,
                             const ThinTrianglePass* thin, const DepthPyramidPass& pyramid, const gpu::Buffer& frame,
                             const PipBuffers& out, shared::PipPush push) const {
  push.pyramidLevels = pyramid.levels();
  push.shadowTexelsAt = gpu::addressHalves(shadowMap.texels());
  push.thinTexelsAt = gpu::addressHalves(thin ? thin->texels() : shadowMap.texels());
  push.tilesAt = gpu::addressHalves(pyramid.tiles());
  if (push.explain) {
    cmd.fillBuffer(out.why.handle(), 0, VK_WHOLE_SIZE, PIP_WHY_NONE);
    gpu::memoryBarrier(cmd, vk::PipelineStageFlagBits2::eClear, vk::AccessFlagBits2::eTransferWrite,
                       vk::PipelineStageFlagBits2::eComputeShader, vk::AccessFlagBits2::eShaderStorageWrite);
  }
  // Without a thin mask the bindings still need an image and a buffer: the shadow map's stand in, unread.
  const vk::ImageView thinView = thin ? thin->depth().view() : shadowMap.depth().view();
  const gpu::ComputePipeline& pipeline = pipeline_(texelReads(shadowMap, thin));
  pipeline.bind(cmd, gpu::Descriptors{}
                         .storageImage(0, gbuffer.position().view())
                         .storageImage(1, gbuffer.normal().view())
                         .sampledImage(2, shadowMap.depth().view(), shadowMap.sampler())
                         .sampledImage(3, thinView, thin ? thin->sampler() : shadowMap.sampler())
                         .buffer(4, frame)
                         .buffer(5, out.visibility)
                         .buffer(6, out.smVisibility)
                         .buffer(7, out.traceFlags)
                         .buffer(8, out.rayMax)
                         .buffer(13, out.count)
                         .buffer(14, out.why)
                         .storageImage(15, gbuffer.faceNormal().view()));
  pipeline.pushConstants(cmd, push);
  cmd.dispatch((gbuffer.width() + PIP_GROUP_SIZE - 1) / PIP_GROUP_SIZE, (gbuffer.height() + PIP_GROUP_SIZE - 1) / PIP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra::raster
