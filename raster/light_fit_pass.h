// Light fit: a directional or spot light's map covers the whole scene, so where the camera sees
// only part of it each texel spans many pixels (wide PIP bands, blocky sm). This pass reduces the
// G-buffer to the receivers' bounds in the map's NDC; fitShadowMap then narrows the map to them.
// Casters need no extra room for hard shadows: a receiver's blockers lie on its ray to the light,
// which the map projects onto the receiver's own texel. (Area lights' blockers do not: their maps
// stay whole-scene.)
#pragma once
#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "shared/frame.h"

namespace penumbra::raster {

// The NDC rectangle of a map's receivers (lo..hi, within [-1, 1]); empty when none were seen.
struct ReceiverBounds {
  glm::vec2 lo{1.0f}, hi{-1.0f};
  std::uint32_t receivers = 0;
};

// `info` (one face) with its face zoomed onto `bounds` grown by marginTexels of the new map on each
// side, square texels kept, zoom at most maxZoom; viewProj and texelWorld change, nothing else.
// Returns info unchanged for cube maps, no receivers, or a fit that would not zoom in.
shared::ShadowMapInfo fitShadowMap(const shared::ShadowMapInfo& info, const ReceiverBounds& bounds, float marginTexels,
                                   float maxZoom);

class LightFitPass {
 public:
  explicit LightFitPass(const gpu::Context& context);
  // Reduces the G-buffer (its writes visible to compute) against info.viewProj[0].
  void record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const shared::ShadowMapInfo& info) const;
  ReceiverBounds bounds() const;  // after the recorded commands ran

 private:
  gpu::ComputePipeline pipeline_;
  gpu::Buffer bounds_;
};

}  // namespace penumbra::raster
