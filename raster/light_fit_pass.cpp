#include "raster/light_fit_pass.h"

#include <algorithm>

#include "light_fit_comp.h"
#include "shared/light_fit.h"

namespace penumbra::raster {
namespace {

constexpr gpu::Binding kBindings[] = {{LIGHT_FIT_BINDING_POSITION, vk::DescriptorType::eStorageImage},
                                      {LIGHT_FIT_BINDING_BOUNDS, vk::DescriptorType::eStorageBuffer}};
static_assert(sizeof(shared::LightFitPush) == 80 && sizeof(shared::LightFitBounds) == 32,
              "light fit structs must match std430 in shared/light_fit.h");

}  // namespace

shared::ShadowMapInfo fitShadowMap(const shared::ShadowMapInfo& info, const ReceiverBounds& bounds, float marginTexels,
                                   float maxZoom) {
  if (info.faceCount != 1 || bounds.receivers == 0) return info;
  const float res = float(info.resolution);
  // Half-extent s (in the old NDC) of a square holding the bounds plus the margin, which is in
  // texels of the new map (2 s / res NDC each): s = e + margin * 2 s / res.
  const glm::vec2 centre = 0.5f * (bounds.lo + bounds.hi);
  const float e = 0.5f * std::max(bounds.hi.x - bounds.lo.x, bounds.hi.y - bounds.lo.y);
  const float denominator = 1.0f - 2.0f * marginTexels / res;
  if (!(denominator > 0.0f)) return info;
  const float s = std::max(e / denominator, 1.0f / maxZoom);
  if (!(s < 1.0f)) return info;
  glm::mat4 zoom(1.0f);  // clip space: x' = (x - c.x w) / s, likewise y
  zoom[0][0] = zoom[1][1] = 1.0f / s;
  zoom[3][0] = -centre.x / s;
  zoom[3][1] = -centre.y / s;
  shared::ShadowMapInfo fitted = info;
  fitted.viewProj[0] = zoom * info.viewProj[0];
  fitted.texelWorld = info.texelWorld * s;
  return fitted;
}

LightFitPass::LightFitPass(const gpu::Context& context)
    : pipeline_(context, light_fit_comp, kBindings, sizeof(shared::LightFitPush), "light fit pipeline"),
      bounds_(context, sizeof(shared::LightFitBounds), vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
              "light fit bounds") {}

void LightFitPass::record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const shared::ShadowMapInfo& info) const {
  const shared::LightFitBounds empty{.minX = 0xffffffffu, .minY = 0xffffffffu, .maxX = 0, .maxY = 0, .receivers = 0};
  cmd.updateBuffer<shared::LightFitBounds>(bounds_.handle(), 0, empty);
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  gpu::memoryBarrier(cmd, Stage::eAllTransfer, Access::eTransferWrite, Stage::eComputeShader,
                     Access::eShaderStorageRead | Access::eShaderStorageWrite);
  pipeline_.bind(cmd, gpu::Descriptors{}
                          .storageImage(LIGHT_FIT_BINDING_POSITION, gbuffer.position().view())
                          .buffer(LIGHT_FIT_BINDING_BOUNDS, bounds_));
  pipeline_.pushConstants(cmd, shared::LightFitPush{.viewProj = info.viewProj[0], .width = gbuffer.width(), .height = gbuffer.height()});
  constexpr std::uint32_t kGroupPixels = LIGHT_FIT_GROUP_SIZE * LIGHT_FIT_BLOCK;
  cmd.dispatch((gbuffer.width() + kGroupPixels - 1) / kGroupPixels, (gbuffer.height() + kGroupPixels - 1) / kGroupPixels, 1);
  gpu::computeToComputeAndHost(cmd);
}

ReceiverBounds LightFitPass::bounds() const {
  const shared::LightFitBounds b = bounds_.download<shared::LightFitBounds>(1).front();
  ReceiverBounds out;
  out.receivers = b.receivers;
  if (b.receivers == 0) return out;
  out.lo = {shared::lightFitFloat(b.minX), shared::lightFitFloat(b.minY)};
  out.hi = {shared::lightFitFloat(b.maxX), shared::lightFitFloat(b.maxY)};
  return out;
}

}  // namespace penumbra::raster
