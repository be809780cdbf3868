// Thin-triangle mask (Lauterbach et al. 2009, section 3.1): a shadow map misses triangles thinner
// than a texel in light space (a wire between texel centres), so their shadows vanish and the PIP
// test never sees them. This pass redraws the scene per light face with a geometry shader that
// keeps only the thin triangles and rasterizes them conservatively (Hasselgren et al. 2005) into a
// depth mask: 1.0 where no thin triangle touches a texel, else the nearest depth of the thin
// triangles touching it. Receivers behind a covered texel are potentially incorrect and get traced.
#pragma once
#include <cstdint>

#include "gpu/pipeline.h"
#include "raster/scene_geometry.h"
#include "raster/shadow_map_pass.h"
#include "shared/frame.h"

namespace penumbra::raster {

// A triangle is thin when, in texel space, its smallest altitude is below maxWidthTexels AND its
// aspect ratio (longest edge / smallest altitude) is at least minAspect: small but regular
// triangles of dense meshes are not enlarged (the paper's point), slivers and edge-on faces are
// (shared::thinTriangle in shaders/shared/thin.h). A triangle crossing a face's near plane is
// clipped there and measured in world space against the texel size at its farthest corner, since
// its texel-space shape diverges at the near plane (see thin_triangles.geom).
struct ThinTriangleSettings {
  float maxWidthTexels = 1.0f;
  float minAspect = 4.0f;
};

class ThinTrianglePass {
 public:
  // Throws std::runtime_error when the device has no geometry shaders, InputError for settings
  // that are not finite and positive (maxWidthTexels) or non-negative (minAspect).
  ThinTrianglePass(const gpu::Context& context, const ShadowMapSettings& settings, std::uint32_t faceCount,
                   ThinTriangleSettings thin = {});
  // Renders info.faceCount faces into the mask (cleared to 1.0, depth test LESS, no bias: the mask
  // must never be farther than the triangle). A thin triangle writes the minimum NDC depth of its
  // (near-clipped) corners to every texel its square touches. Leaves the mask in SHADER_READ_ONLY
  // layout for compute reads.
  void record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const shared::ShadowMapInfo& info) const;
  const gpu::Image& depth() const { return depth_; }  // D32, one layer per face, arrayed view
  vk::Sampler sampler() const { return *sampler_; }
  std::uint32_t faceCount() const { return depth_.desc().layers; }
  const ThinTriangleSettings& thinSettings() const { return thin_; }

 private:
  ShadowMapSettings settings_;
  ThinTriangleSettings thin_;
  gpu::Image depth_;
  vk::raii::Sampler sampler_;
  gpu::GraphicsPipeline pipeline_;
};

}  // namespace penumbra::raster
