// Method msm: the area light approximated by K point lights at its stratified sample points
// (K = settings.msmMaps), one shadow map each, and visibility the average of the K unfiltered
// lookups. Every pixel sees the same K points (pixel index 0), so the error is banding between
// K hard shadows rather than per-pixel noise; it converges to the reference as K grows.
//
// Per map: render it into the method's own map image, then run the shared lookup in accumulate
// mode (adding 1/K of its answer) against a FrameData copy whose .shadow is that sample's
// projection. The copy keeps the centre light in .light, so lightReaches() -- and therefore the
// zero outside a spot's cone or behind a rect/disk -- is the same rule sm applies.
//
// Timer scopes: with K <= kMaxTimedMaps each map adds a "shadow_map" and a "lookup" scope, which
// FrameStats sums by name. The frame's timer holds 32 scopes (gbuffer and shade use two), so for
// larger K a single "shadow_maps_and_lookups" scope covers the whole loop instead.
#include <algorithm>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "hybrid/frame_context.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"

namespace penumbra {
namespace {

constexpr std::uint32_t kMaxTimedMaps = 12;

// The visibility buffer is read and written by every accumulating lookup.
void visibilityBarrier(const vk::raii::CommandBuffer& cmd, vk::PipelineStageFlags2 srcStage, vk::AccessFlags2 srcAccess) {
  const vk::MemoryBarrier2 barrier{.srcStageMask = srcStage,
                                   .srcAccessMask = srcAccess,
                                   .dstStageMask = vk::PipelineStageFlagBits2::eComputeShader,
                                   .dstAccessMask = vk::AccessFlagBits2::eShaderStorageRead | vk::AccessFlagBits2::eShaderStorageWrite};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &barrier});
}

class MultiMapMethod final : public Method {
 public:
  std::uint32_t samplesPerPixel(const RenderSettings& settings) const override { return settings.msmMaps; }

  bool readsShadowMap() const override { return true; }  // for point-like lights (below)

  void run(FrameContext& r, FrameStats& stats) override {
    const shared::FrameData& centre = r.frameData();
    // A point-like light has one sample point, the centre: one map, which is exactly sm's.
    const std::uint32_t k = shared::isAreaLight(centre.light) ? std::max(r.settings().msmMaps, 1u) : 1u;
    // One FrameData per map, kept across frames and rewritten.
    while (frames_.size() < k) {
      frames_.emplace_back(r.context(), sizeof(shared::FrameData), vk::BufferUsageFlagBits::eStorageBuffer, "msm frame data");
    }
    std::vector<shared::ShadowMapInfo> infos;
    for (std::uint32_t s = 0; s < k; ++s) {
      shared::GpuLight point = centre.light;
      point.position = glm::vec4(shared::lightSamplePoint(centre.light, 0u, s, k), 1.0f);
      point.size = 0.0f;
      shared::FrameData data = centre;
      // A point-like light's one map is the centre map, as sm has it (fitted to the view, if so).
      data.shadow = k == 1 ? centre.shadow : raster::makeShadowMapInfo(point, r.bounds(), r.settings().shadowMap);
      data.shadowFilter = FILTER_NONE;
      frames_[s].upload(std::span<const shared::FrameData>(&data, 1));
      infos.push_back(data.shadow);
      const std::pair key(data.shadow.faceCount, data.shadow.resolution);
      if (!maps_.contains(key)) {
        // Samples of one light can straddle the scene's bounding sphere: perspective and cube maps
        // (and a point-like light's centre map has the resolution its footprint gives it).
        raster::ShadowMapSettings settings = r.settings().shadowMap;
        settings.resolution = data.shadow.resolution;
        maps_[key] = std::make_unique<raster::ShadowMapPass>(r.context(), settings, data.shadow.faceCount);
      }
    }
    std::uint64_t mapBytes = 0;
    for (const auto& [faces, map] : maps_) mapBytes += map->depth().bytes();
    stats.memoryBytes["shadow_map"] = mapBytes;

    const bool timeEach = k <= kMaxTimedMaps;
    const float weight = 1.0f / float(k);
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      if (!timeEach) r.timer().begin(cmd, "shadow_maps_and_lookups");
      cmd.fillBuffer(r.visibility().handle(), 0, VK_WHOLE_SIZE, 0u);  // 0.0f: the lookups add to it
      visibilityBarrier(cmd, vk::PipelineStageFlagBits2::eClear, vk::AccessFlagBits2::eTransferWrite);
      for (std::uint32_t s = 0; s < k; ++s) {
        const raster::ShadowMapPass& map = *maps_.at({infos[s].faceCount, infos[s].resolution});
        // Rendering map s+1 waits for lookup s's reads: recordLightFaces' first transition
        // has all commands as its source stage.
        if (timeEach) r.timer().begin(cmd, "shadow_map");
        map.record(cmd, r.geometry(), infos[s]);
        if (timeEach) r.timer().end(cmd);
        if (timeEach) r.timer().begin(cmd, "lookup");
        r.shadowLookup().record(cmd, r.gbuffer(), map, frames_[s], r.visibility(), r.lightRect(), weight);
        visibilityBarrier(cmd, vk::PipelineStageFlagBits2::eComputeShader, vk::AccessFlagBits2::eShaderStorageWrite);
        if (timeEach) r.timer().end(cmd);
      }
      if (!timeEach) r.timer().end(cmd);
      r.recordShade(cmd);
    });
  }

 private:
  // Kept across frames (the Renderer keeps its methods): made once per face count.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::unique_ptr<raster::ShadowMapPass>>
      maps_;  // by faces, resolution
  std::vector<gpu::Buffer> frames_;
};

}  // namespace

void register_multi_map_method(Registry& r) {
  r.method("msm", [] { return std::make_unique<MultiMapMethod>(); });
}

}  // namespace penumbra
