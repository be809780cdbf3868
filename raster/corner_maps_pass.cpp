#include "raster/corner_maps_pass.h"

#include <span>

namespace penumbra::raster {

CornerMapsPass::CornerMapsPass(const gpu::Context& context, const ShadowMapSettings& settings)
    : context_(context), settings_(settings) {}

void CornerMapsPass::record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const GBufferPass& gbuffer,
                            const PipClassifyPass& classify, const shared::FrameData& frame, const Bounds& bounds,
                            const PipBuffers& out, const PipSettings& pip) {
  auto cornerInfo = [&](std::uint32_t i, bool forceCube) {
    shared::GpuLight corner = frame.light;
    corner.position = glm::vec4(shared::lightCorner(frame.light, i), 1.0f);
    return makeShadowMapInfo(corner, bounds, settings_, forceCube);
  };
  std::array<shared::ShadowMapInfo, 4> infos;
  bool cube = false;
  for (std::uint32_t i = 0; i < 4; ++i) {
    infos[i] = cornerInfo(i, false);
    cube = cube || infos[i].kind == SHADOW_CUBE;
  }
  // One image serves every corner, so all of them take the cube if one needs it.
  if (cube) for (std::uint32_t i = 0; i < 4; ++i) infos[i] = cornerInfo(i, true);
  const std::uint32_t faces = infos[0].faceCount;
  if (!map_ || map_->faceCount() != faces) {
    map_ = std::make_unique<ShadowMapPass>(context_, settings_, faces);
    pyramid_ = std::make_unique<DepthPyramidPass>(context_, settings_.resolution, faces);
  }
  for (std::uint32_t i = 0; i < 4; ++i) {
    shared::FrameData data = frame;
    data.shadow = infos[i];
    if (!frames_[i]) frames_[i].emplace(context_, sizeof(shared::FrameData), vk::BufferUsageFlagBits::eStorageBuffer, "corner frame data");
    frames_[i]->upload(std::span<const shared::FrameData>(&data, 1));
    // Thin geometry is the centre pass's thin mask's job; rays stay whole (area light).
    shared::PipPush push = PipClassifyPass::pushFor(pip, infos[i], false, bounds.radius());
    push.cornerUnion = 1u;
    push.useIntervals = 0u;
    push.appendList = 0u;
    map_->record(cmd, geometry, infos[i]);
    pyramid_->record(cmd, *map_, nullptr, infos[i], push.deltaThreshold);
    // explained: the pixels a corner map adds to the mask (PIP_MASK_CORNER)
    classify.record(cmd, gbuffer, *map_, nullptr, *pyramid_, *frames_[i], out, push, pip.explain);
  }
}

vk::DeviceSize CornerMapsPass::bytes() const { return map_ ? map_->depth().bytes() + pyramid_->tiles().size() : 0; }

}  // namespace penumbra::raster
