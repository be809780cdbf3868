#include "hybrid/shade_pass.h"

#include "shade_comp.h"
#include "shared/raster.h"

namespace penumbra {
namespace {

constexpr gpu::Binding kBindings[] = {{0, vk::DescriptorType::eStorageImage},  {1, vk::DescriptorType::eStorageImage},
                                      {2, vk::DescriptorType::eStorageImage},  {3, vk::DescriptorType::eStorageBuffer},
                                      {4, vk::DescriptorType::eStorageBuffer}, {5, vk::DescriptorType::eStorageBuffer},
                                      {6, vk::DescriptorType::eStorageBuffer}};

}  // namespace

ShadePass::ShadePass(const gpu::Context& context) : pipeline_(context, shade_comp, kBindings, sizeof(std::uint32_t), "shade pipeline") {}

void ShadePass::record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                       const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& color,
                       Term term) const {
  pipeline_.bind(cmd, gpu::Descriptors{}
                          .storageImage(0, gbuffer.position().view())
                          .storageImage(1, gbuffer.normal().view())
                          .storageImage(2, gbuffer.albedo().view())
                          .buffer(3, frame)
                          .buffer(4, visibility)
                          .buffer(5, color)
                          .buffer(6, indirect));
  pipeline_.pushConstants(cmd, std::uint32_t(term));
  cmd.dispatch((gbuffer.width() + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE,
               (gbuffer.height() + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra
