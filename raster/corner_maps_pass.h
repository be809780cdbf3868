// --penumbra-maps 5 (Lauterbach et al. 2009, 3.2): shadow maps from the area light's four corners,
// each with its edge pyramid, whose edges' splats are added to the centre map's penumbra mask by
// the classification pass in its corner mode. One map image and one pyramid serve the corners in
// turn (the map pass's layout transition orders each render after the previous corner's reads).
#pragma once
#include <array>
#include <memory>
#include <optional>

#include "raster/depth_pyramid_pass.h"
#include "raster/pip_classify_pass.h"
#include "raster/shadow_map_pass.h"

namespace penumbra::raster {

class CornerMapsPass {
 public:
  CornerMapsPass(const gpu::Context& context, const ShadowMapSettings& settings);
  // After the centre pass classified into out.traceFlags; frame is the centre pass's frame data
  // (an area light); pip: the centre pass's settings (thresholds, margins; no thin mask here).
  void record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const GBufferPass& gbuffer,
              const PipClassifyPass& classify, const shared::FrameData& frame, const Bounds& bounds, const PipBuffers& out,
              const PipSettings& pip);
  vk::DeviceSize bytes() const;  // the map and pyramid (0 before the first record)

 private:
  const gpu::Context& context_;
  ShadowMapSettings settings_;
  std::unique_ptr<ShadowMapPass> map_;
  std::unique_ptr<DepthPyramidPass> pyramid_;
  std::array<std::optional<gpu::Buffer>, 4> frames_;  // each corner's frame data (its map's projection)
};

}  // namespace penumbra::raster
