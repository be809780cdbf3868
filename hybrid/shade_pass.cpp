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
                                      {SHADE_BINDING_DIRECT, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_LIGHTS, vk::DescriptorType::eStorageBuffer},
                                      {SHADE_BINDING_TILES, vk::DescriptorType::eStorageBuffer}};

}  // namespace

ShadePass::ShadePass(const gpu::Context& context)
    : pipeline_(context, shade_comp, kBindings, sizeof(shared::ShadePush), "shade pipeline") {}

void ShadePass::record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                       const gpu::Buffer& visibility, const gpu::Buffer& indirect, const gpu::Buffer& color,
                       Term term) const {
  shared::ShadePush push{};
  push.term = std::uint32_t(term);
  push.last = 1u;
  // one light: the shader touches neither the direct sum nor a batch's lists (any buffer will do)
  dispatch(cmd, gbuffer, frame, visibility, indirect, indirect, color, indirect, indirect, push,
           {0u, 0u, gbuffer.width(), gbuffer.height()});
}

void ShadePass::record(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer, const gpu::Buffer& frame,
                       const gpu::Buffer& visibility, const gpu::Buffer& direct, const gpu::Buffer& color,
                       const ShadeBatch& batch, const glm::uvec4& rect) const {
  shared::ShadePush push{};
  push.origin = glm::uvec2(rect);
  push.term = std::uint32_t(Term::Shadow);  // the methods that take several lights
  push.batched = 1u;
  push.last = batch.last ? 1u : 0u;
  push.sum = batch.sum ? 1u : 0u;
  push.tilesX = batch.tilesX;
  // the indirect binding: a method of several lights has no indirect term (any buffer will do)
  dispatch(cmd, gbuffer, frame, visibility, direct, direct, color, batch.lights, batch.tiles, push, rect);
}

void ShadePass::dispatch(const vk::raii::CommandBuffer& cmd, const raster::GBufferPass& gbuffer,
                         const gpu::Buffer& frame, const gpu::Buffer& visibility, const gpu::Buffer& indirect,
                         const gpu::Buffer& direct, const gpu::Buffer& color, const gpu::Buffer& lights,
                         const gpu::Buffer& tiles, const shared::ShadePush& push, const glm::uvec4& rect) const {
  pipeline_.bind(cmd, gpu::Descriptors{}
                          .storageImage(SHADE_BINDING_POSITION, gbuffer.position().view())
                          .storageImage(SHADE_BINDING_NORMAL, gbuffer.normal().view())
                          .storageImage(SHADE_BINDING_ALBEDO, gbuffer.albedo().view())
                          .buffer(SHADE_BINDING_FRAME, frame)
                          .buffer(SHADE_BINDING_VISIBILITY, visibility)
                          .buffer(SHADE_BINDING_COLOR, color)
                          .buffer(SHADE_BINDING_INDIRECT, indirect)
                          .buffer(SHADE_BINDING_DIRECT, direct)
                          .buffer(SHADE_BINDING_LIGHTS, lights)
                          .buffer(SHADE_BINDING_TILES, tiles));
  pipeline_.pushConstants(cmd, push);
  cmd.dispatch((rect.z - rect.x + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE,
               (rect.w - rect.y + LOOKUP_GROUP_SIZE - 1) / LOOKUP_GROUP_SIZE, 1);
  gpu::computeToComputeAndHost(cmd);
}

}  // namespace penumbra
