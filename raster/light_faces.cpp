#include "raster/light_faces.h"

#include <stdexcept>

namespace penumbra::raster {

void recordLightFaces(const vk::raii::CommandBuffer& cmd, const gpu::Image& depth, const shared::ShadowMapInfo& info,
                      const std::function<void(std::uint32_t face)>& drawFace, const gpu::Buffer* texels) {
  if (info.faceCount != depth.desc().layers || info.resolution != depth.desc().width) {
    throw std::logic_error(depth.desc().name + ": shadow map info does not match the image's faces or resolution");
  }
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  gpu::transition(cmd, depth, {vk::ImageLayout::eUndefined, vk::ImageLayout::eDepthAttachmentOptimal, Stage::eAllCommands,
                               Access::eMemoryRead, Stage::eEarlyFragmentTests | Stage::eLateFragmentTests,
                               Access::eDepthStencilAttachmentWrite | Access::eDepthStencilAttachmentRead});
  const std::uint32_t res = info.resolution;
  const vk::Rect2D area{{0, 0}, {res, res}};
  for (std::uint32_t face = 0; face < info.faceCount; ++face) {
    const vk::RenderingAttachmentInfo attachment{.imageView = depth.layerView(face),
                                                 .imageLayout = vk::ImageLayout::eDepthAttachmentOptimal,
                                                 .loadOp = vk::AttachmentLoadOp::eClear,
                                                 .storeOp = vk::AttachmentStoreOp::eStore,
                                                 .clearValue = vk::ClearValue{.depthStencil = {.depth = 1.0f, .stencil = 0}}};
    cmd.beginRendering({.renderArea = area, .layerCount = 1, .pDepthAttachment = &attachment});
    cmd.setViewport(0, vk::Viewport{0.0f, 0.0f, float(res), float(res), 0.0f, 1.0f});
    cmd.setScissor(0, area);
    drawFace(face);
    cmd.endRendering();
  }
  if (!texels) {
    gpu::transition(cmd, depth, {vk::ImageLayout::eDepthAttachmentOptimal, vk::ImageLayout::eShaderReadOnlyOptimal,
                                 Stage::eLateFragmentTests, Access::eDepthStencilAttachmentWrite, Stage::eComputeShader,
                                 Access::eShaderSampledRead});
    return;
  }
  if (texels->size() < depth.bytes()) throw std::logic_error(depth.desc().name + ": texel buffer too small");
  gpu::transition(cmd, depth, {vk::ImageLayout::eDepthAttachmentOptimal, vk::ImageLayout::eTransferSrcOptimal,
                               Stage::eLateFragmentTests, Access::eDepthStencilAttachmentWrite, Stage::eCopy,
                               Access::eTransferRead});
  const vk::BufferImageCopy region{.imageSubresource = {depth.aspect(), 0, 0, depth.desc().layers},
                                   .imageExtent = {res, res, 1}};
  cmd.copyImageToBuffer(depth.handle(), vk::ImageLayout::eTransferSrcOptimal, texels->handle(), region);
  gpu::transition(cmd, depth, {vk::ImageLayout::eTransferSrcOptimal, vk::ImageLayout::eShaderReadOnlyOptimal, Stage::eCopy,
                               Access::eNone, Stage::eComputeShader, Access::eShaderSampledRead});
  gpu::memoryBarrier(cmd, Stage::eCopy, Access::eTransferWrite, Stage::eComputeShader, Access::eShaderStorageRead);
}

}  // namespace penumbra::raster
