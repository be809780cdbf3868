// Bitmask visibility sampling (Eisemann & Décoret 2007) for planar receivers: which of up to
// BITMASK_MAX_SAMPLES light samples each texel of the receiver's hidden-samples map cannot see,
// from one raster pass over the casters, no shadow map and no rays.
//  - table (bitmask_table.comp, BitmaskTable): the Hough table of the shared sample pattern,
//    rebuilt when the light, the samples or the frame's pattern change, shared by the receivers;
//  - fit (bitmask_fit.comp): a receiver's map narrowed to its part the camera sees;
//  - hidden (bitmask_hidden.{vert,geom,frag}): each caster's influence region on the map; per
//    fragment the triangle back-projected onto the light and its three edges' masks ANDed, ORed
//    into the texel's bits (atomicOr in a storage buffer: any number of words per texel);
//  - resolve (bitmask_resolve.comp): receiver pixels' visibility from their texel's bits; every
//    other covered pixel flagged for the fallback tracer.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/options.h"
#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "raster/scene_geometry.h"
#include "shared/bitmask.h"
#include "shared/light.h"

namespace penumbra::raster {

constexpr std::size_t kMaxBitmaskReceivers = 4;

struct BitmaskSettings {
  std::uint32_t resolution = 512;  // texels per side of the receiver's hidden-samples map
  // The receiver meshes' names; empty: the planar meshes of at least 1% of the largest one's area
  // (at most kMaxBitmaskReceivers, largest first).
  std::vector<std::string> receivers;
  std::string fallback = "srt";    // how the other pixels are answered: srt (classified, PIP traced) or frt (all traced)
  bool watertight = false;         // the casters are closed surfaces wound counter-clockwise: drop their front faces
  bool decorrelate = false;        // each texel sees the pattern under one of the square's symmetries (texelSymmetry)
};

// The command line's options of method bitmask (--bitmask-res, --bitmask-receivers, ...).
const Options<BitmaskSettings>& bitmaskOptions();

// The Hough table (bitmask_table.comp) of the shared pattern's samples under one light: built when
// the light's type, the sample count or the frame's pattern shift change, shared by every
// receiver's pass.
class BitmaskTable {
 public:
  explicit BitmaskTable(const gpu::Context& context);
  // Builds the table for `light` and `samples` unless the last one holds.
  void record(const vk::raii::CommandBuffer& cmd, const shared::GpuLight& light, std::uint32_t samples);
  const gpu::Buffer& buffer() const { return *table_; }  // BITMASK_THETA_BINS * R_BINS * words
  std::uint32_t words() const { return words_; }
  bool reused() const { return reused_; }

 private:
  const gpu::Context& context_;
  gpu::ComputePipeline pipeline_;
  gpu::Buffer light_;
  std::optional<gpu::Buffer> table_;
  std::uint32_t words_ = 0;
  struct Key {  // what the table was built for
    std::uint32_t type, samples, sampleFrame;
    bool operator==(const Key&) const = default;
  };
  std::optional<Key> built_;
  bool reused_ = false;
};

// One receiver's hidden-samples map and its resolve.
class BitmaskPass {
 public:
  // Throws std::runtime_error when the device lacks geometry shaders or fragment atomics.
  BitmaskPass(const gpu::Context& context, std::uint32_t resolution);
  // The hidden-samples map of `frame`'s receiver rectangle as it is (texel centres at its
  // (i + 1/2) / resolution points) with `table` (recorded before, for frame.samples), left for
  // compute and host reads.
  void recordHidden(const vk::raii::CommandBuffer& cmd, const BitmaskTable& table, const SceneGeometry& geometry,
                    const shared::BitmaskFrame& frame);
  // The map fitted to the receiver's pixels in the G-buffer, a height field's heights (`field`: its
  // mesh alone; null for a plane), the hidden samples, then the resolve into visibility and
  // traceFlags. `frameData`: the renderer's FrameData.
  void record(const vk::raii::CommandBuffer& cmd, const BitmaskTable& table, const SceneGeometry& geometry,
              const SceneGeometry* field, const GBufferPass& gbuffer, const gpu::Buffer& frameData,
              const shared::BitmaskFrame& frame, const gpu::Buffer& visibility, const gpu::Buffer& traceFlags);
  const gpu::Buffer& hidden() const { return *hidden_; }  // resolution^2 * words
  vk::DeviceSize bytes() const;
  // After the recorded frame ran: influence regions drawn and their texels (about the fragments).
  std::pair<std::uint32_t, std::uint64_t> fill() const {
    const auto words = fill_.download<std::uint32_t>(3);
    return {words[0], words[1] | std::uint64_t(words[2]) << 32};
  }

 private:
  void upload(const shared::BitmaskFrame& frame);
  // The map's rectangle narrowed to the receiver pixels of the G-buffer (bitmask_fit.comp).
  void recordFit(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer);
  void recordDraw(const vk::raii::CommandBuffer& cmd, const BitmaskTable& table, const SceneGeometry& geometry);
  // Draws `geometry` with `pipeline` over the map's texels.
  void drawOverMap(const vk::raii::CommandBuffer& cmd, const gpu::GraphicsPipeline& pipeline,
                   const gpu::Descriptors& descriptors, const SceneGeometry& geometry) const;

  const gpu::Context& context_;
  std::uint32_t resolution_;
  gpu::ComputePipeline fitPipeline_;
  gpu::GraphicsPipeline hiddenPipeline_;
  gpu::GraphicsPipeline heightPipeline_;
  gpu::ComputePipeline resolvePipeline_;
  gpu::Buffer frame_;
  gpu::Buffer bounds_;
  gpu::Buffer fill_;
  std::optional<gpu::Buffer> hidden_;
  std::optional<gpu::Buffer> heights_;  // a height field's, per texel (a 4-byte stand-in for a plane)
  std::uint32_t words_ = 0;
};

}  // namespace penumbra::raster
