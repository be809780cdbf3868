#include "hybrid/shade_pass.h"

#include "shade_comp.h"
#include "shared/raster.h"

namespace penumbra {
namespace {

constexpr gpu::Binding kBindings[] = {{SHADE_BINDING_POSITION, vk::DescriptorType::eStorageImage},
                                      {SHADE_BINDING_NORMAL, vk::DescriptorType::eStorageImage},
                                      {SHADE_BINDING_ALBEDO, vk::DescriptorType::eStorageImage},
                                      {SHADE_BINDING_FRAME, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_VISIBILITY, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_COLOR, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_INDIRECT, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_DIRECT, vk::DescriptorType::eStorageBuffer}};

}  // namespace

ShadePass::ShadePass(const gpu::Context& context)
    : pipeline_(context, shade_comp, kBindings, sizeof(shared::ShadePush), "shade pipeline") {}

void ShadePass::record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                       const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& direct,
                       const gpu::Buffer& color, Term term, std::uint32_t light, std::uint32_t lights,
                       const glm::uvec4& rect) const {
  pipeline_.bind(cmd, gpu::Descriptors{}
                          .storageImage(SHADE_BINDING_POSITION, gbuffer.position().view())
                          .storageImage(SHADE_BINDING_NORMAL, gbuffer.normal().view())
                          .storageImage(SHADE_BINDING_ALBEDO, gbuffer.albedo().view())
                          .buffer(SHADE_BINDING_FRAME, frame)
                          .buffer(SHADE_BINDING_VISIBILITY, visibility)
                          .buffer(SHADE_BINDING_COLOR, color)
                          .buffer(SHADE_BINDING_INDIRECT, indirect)
                          .buffer(SHADE_BINDING_DIRECT, direct));
  pipeline_.pushConstants(cmd, shared::ShadePush{glm::uvec2(rect), std::uint32_t(term), light, lights});
  cmd.dispatch((rect.z - rect.x + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE,
               (rect.w - rect.y + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra
