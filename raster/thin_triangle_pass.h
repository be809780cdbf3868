// Thin-triangle mask (Lauterbach et al. 2009, section 3.1): a shadow map misses triangles thinner
// than a texel in light space (a wire between texel centres), so their shadows vanish and the PIP
// test never sees them. This pass redraws the scene per light face with a geometry shader that
// keeps only the thin triangles and rasterizes them conservatively (Hasselgren et al. 2005) into a
// depth mask: 1.0 where no thin triangle touches a texel, else the nearest depth of the thin
// triangles touching it. Receivers behind a covered texel are potentially incorrect and get traced.
// The mask is dilated by THIN_DILATE_TEXELS (shared/thin.h): classification reads one texel for its
// 3x3 neighbourhood. Only thin triangles are drawn: a compute pass (thin_select.comp) lists them
// per face; list and mask are kept while the faces' matrices and the geometry stay the same.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>

#include "core/options.h"
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
  // Thin triangles listed per face; 0: a quarter of the scene's, at least 65536. A face with more
  // draws the whole scene instead (the geometry shader still keeps only the thin ones).
  std::uint32_t listCapacity = 0;
};

// The command line's options of the thin-triangle pass (--thin-width, --thin-aspect).
const Options<ThinTriangleSettings>& thinOptions();

class ThinTrianglePass {
 public:
  // Throws std::runtime_error when the device has no geometry shaders, InputError for settings
  // that are not finite and positive (maxWidthTexels) or non-negative (minAspect).
  ThinTrianglePass(const gpu::Context& context, const ShadowMapSettings& settings, std::uint32_t faceCount,
                   ThinTriangleSettings thin = {});
  // Renders info.faceCount faces into the mask (cleared to 1.0, depth test LESS, no bias: the mask
  // must never be farther than the triangle). A thin triangle writes, to every texel within
  // THIN_DILATE_TEXELS of a texel its square touches, the least NDC depth of its plane over that
  // texel's block (within its corners' depths; edge-on or near-clipped: its nearest corner's).
  // Selects the thin triangles first; when the last record was for the same faces and geometry
  // version, records nothing: that mask still holds. Leaves the mask in SHADER_READ_ONLY layout for
  // compute reads (a caller that changes the layout must restore it).
  void record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const shared::ShadowMapInfo& info);
  // After the recorded frame ran: thin triangles summed over faces, and whether record() reused the
  // previous selection.
  std::uint64_t thinTriangles() const;
  bool selectionReused() const { return reused_; }
  vk::DeviceSize bytes() const;  // mask, list and draws
  const gpu::Image& depth() const { return depth_; }  // D32, one layer per face, arrayed view
  const gpu::Buffer& texels() const { return texels_; }  // see ShadowMapPass::texels
  bool hasTexelCopy() const { return texelCopy(texels_, depth_) != nullptr; }
  vk::Sampler sampler() const { return *sampler_; }
  std::uint32_t faceCount() const { return depth_.desc().layers; }
  const ThinTriangleSettings& thinSettings() const { return thin_; }

 private:
  ShadowMapSettings settings_;
  ThinTriangleSettings thin_;
  gpu::Image depth_;
  gpu::Buffer texels_;
  vk::raii::Sampler sampler_;
  gpu::GraphicsPipeline pipeline_;
  gpu::ComputePipeline select_;

  // What the list was selected for.
  struct Selection {
    const SceneGeometry* geometry;
    std::uint64_t version;
    float texelWorld;
    std::array<glm::mat4, SHADOW_MAX_FACES> viewProj;
    bool operator==(const Selection&) const = default;
  };
  void recordSelection(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const shared::ShadowMapInfo& info);
  const gpu::Context& context_;
  std::optional<Selection> selection_;
  bool reused_ = false;
  std::uint32_t capacity_ = 0;        // triangles per face in the list
  std::unique_ptr<gpu::Buffer> list_;   // indices, faceCount * capacity_ * 3
  gpu::Buffer draws_;                 // THIN_DRAW_WORDS uints per face
};

// Whether passes that read the shadow map and its thin mask (thin may be null) read texel copies.
inline bool texelReads(const ShadowMapPass& shadowMap, const ThinTrianglePass* thin) {
  return shadowMap.hasTexelCopy() && (!thin || thin->hasTexelCopy());
}

}  // namespace penumbra::raster
