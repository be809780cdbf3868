// Light pass: depth shadow map(s) of the whole scene as seen from the light.
//   directional            -> one orthographic face fitted to the scene's bounding sphere
//   spot, or a light outside the bounding sphere -> one perspective face aimed at the scene
//   a light inside the bounding sphere           -> a cube: six 90-degree faces
// Slope-scaled depth bias is applied by the rasterizer; the normal offset by the lookups.
#pragma once
#include <cstdint>

#include "core/options.h"
#include "core/scene.h"
#include "gpu/pipeline.h"
#include "raster/scene_geometry.h"
#include "shared/frame.h"

namespace penumbra::raster {

struct ShadowMapSettings {
  std::uint32_t resolution = 2048;
  float depthBiasConstant = 1.0f;  // in units of the minimum resolvable depth difference
  // Times the triangle's depth slope. 0: the map holds the surfaces' own depths, so srt's
  // classification can tell a layer a hair above a receiver from the receiver (pip_classify.comp
  // layerOver), and the receiver-side normal offset keeps acne away (1.5 made sm 0.43 -> 1.1%
  // wrong on FZK-Haus by shifting shadows off their casters).
  float depthBiasSlope = 0.0f;
  float normalOffsetTexels = 0.75f;
  // How compute passes read the light's depth maps (shadow map, thin mask): Texture, as sampled
  // images (right on a GPU), or Buffer, from a copy in a storage buffer (on lavapipe a sampled
  // fetch costs several storage loads); Auto picks Buffer on CPU devices (bufferReads()).
  enum class Reads { Auto, Texture, Buffer } reads = Reads::Auto;
};

// settings.reads resolved for this device: true when the maps get texel copies, which the passes
// then read (their pipelines are specialized on it: hasTexelCopy()).
// The command line's options of the light's maps (--shadow-map-res, the biases, --shadow-reads).
const Options<ShadowMapSettings>& shadowMapOptions();

bool bufferReads(const gpu::Context& context, const ShadowMapSettings& settings);
// The texel copy of a light depth map for those reads (a 4-byte stand-in when they are off).
gpu::Buffer makeTexelBuffer(const gpu::Context& context, const gpu::Image& depth, const ShadowMapSettings& settings);
// `texels` when it is such a copy of `depth` (not the stand-in): where recordLightFaces copies to.
inline const gpu::Buffer* texelCopy(const gpu::Buffer& texels, const gpu::Image& depth) {
  return texels.size() >= depth.bytes() ? &texels : nullptr;
}

// Projection(s) for `light` covering `bounds`; pure math, no GPU. forceCube: six faces even where
// one would do (maps that must share one image layout).
// A cube map's near plane without a clearance, as a fraction of its far plane.
constexpr float kCubeNearFraction = 1e-4f;

// clearance: the distance from the light to the nearest geometry (distanceToNearestTriangle), or 0
// when unknown: a cube map's near plane goes out to half of it (at most 1% of the far plane).
shared::ShadowMapInfo makeShadowMapInfo(const shared::GpuLight& light, const Bounds& bounds, const ShadowMapSettings& settings,
                                        bool forceCube = false, float clearance = 0.0f);

class ShadowMapPass {
 public:
  ShadowMapPass(const gpu::Context& context, const ShadowMapSettings& settings, std::uint32_t faceCount);
  // Renders info.faceCount faces; leaves the map in SHADER_READ_ONLY layout for compute lookups.
  void record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const shared::ShadowMapInfo& info) const;
  const gpu::Image& depth() const { return depth_; }
  // One float per texel, face after face; a small stand-in when the passes read the image.
  const gpu::Buffer& texels() const { return texels_; }
  bool hasTexelCopy() const { return texelCopy(texels_, depth_) != nullptr; }
  vk::Sampler sampler() const { return *sampler_; }
  std::uint32_t faceCount() const { return depth_.desc().layers; }

 private:
  ShadowMapSettings settings_;
  gpu::Image depth_;
  gpu::Buffer texels_;
  vk::raii::Sampler sampler_;
  gpu::GraphicsPipeline pipeline_;
  gpu::GraphicsPipeline cutoutPipeline_;  // cut-out meshes: no depth where their texture cuts them away
};

}  // namespace penumbra::raster
