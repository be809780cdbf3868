// Bitmask visibility sampling (Eisemann & Décoret 2007) for one planar receiver: which of up to
// BITMASK_MAX_SAMPLES light samples each texel of the receiver's hidden-samples map cannot see,
// from one raster pass over the casters, no shadow map and no rays.
//  - fit (bitmask_fit.comp): the map narrowed to the receiver's part the camera sees;
//  - table (bitmask_table.comp): the Hough table of the shared sample pattern, rebuilt when the
//    light, the samples or the frame's pattern change;
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

#include "gpu/pipeline.h"
#include "raster/gbuffer_pass.h"
#include "raster/scene_geometry.h"
#include "shared/bitmask.h"
#include "shared/light.h"

namespace penumbra::raster {

struct BitmaskSettings {
  std::uint32_t resolution = 512;  // texels per side of the receiver's hidden-samples map
  std::string receiver;            // the receiver mesh's name; empty: the largest planar mesh
  std::string fallback = "srt";    // how the other pixels are answered: srt (classified, PIP traced) or frt (all traced)
  bool watertight = false;         // the casters are closed surfaces wound counter-clockwise: drop their front faces
  bool decorrelate = false;        // each texel sees the pattern under one of the square's symmetries (texelSymmetry)
};

class BitmaskPass {
 public:
  // Throws std::runtime_error when the device lacks geometry shaders or fragment atomics.
  BitmaskPass(const gpu::Context& context, std::uint32_t resolution);
  // Uploads the frame and the light and builds the Hough table for them unless the last one holds
  // (same light type, samples and sample frame); record() starts with it.
  void recordTable(const vk::raii::CommandBuffer& cmd, const shared::GpuLight& light, const shared::BitmaskFrame& frame);
  // After recordTable: the hidden-samples map of the uploaded frame's receiver rectangle as it is
  // (texel centres at its (i + 1/2) / resolution points), left for compute and host reads.
  void recordHidden(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry);
  // The hidden-samples map of `frame`'s receiver under `light` (frame.samples, frame.words set),
  // then the resolve into visibility and traceFlags. `frameData`: the renderer's FrameData.
  void record(const vk::raii::CommandBuffer& cmd, const SceneGeometry& geometry, const GBufferPass& gbuffer,
              const gpu::Buffer& frameData, const shared::GpuLight& light, const shared::BitmaskFrame& frame,
              const gpu::Buffer& visibility, const gpu::Buffer& traceFlags);
  const gpu::Buffer& table() const { return *table_; }    // for tests: BITMASK_THETA_BINS * R_BINS * words
  const gpu::Buffer& hidden() const { return *hidden_; }  // resolution^2 * words
  vk::DeviceSize bytes() const;
  // After the recorded frame ran: influence regions drawn and their texels (about the fragments;
  // each region's count capped at 4M).
  std::pair<std::uint32_t, std::uint32_t> fill() const {
    const auto words = fill_.download<std::uint32_t>(2);
    return {words[0], words[1]};
  }
  bool tableReused() const { return reused_; }

 private:
  // The map's rectangle narrowed to the receiver pixels of the G-buffer (bitmask_fit.comp).
  void recordFit(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer);

  const gpu::Context& context_;
  std::uint32_t resolution_;
  gpu::ComputePipeline tablePipeline_;
  gpu::ComputePipeline fitPipeline_;
  gpu::GraphicsPipeline hiddenPipeline_;
  gpu::ComputePipeline resolvePipeline_;
  gpu::Buffer frame_;
  gpu::Buffer light_;
  gpu::Buffer bounds_;
  gpu::Buffer fill_;
  std::optional<gpu::Buffer> table_, hidden_;
  std::uint32_t words_ = 0;
  struct TableKey {  // what the table was built for
    std::uint32_t type, samples, sampleFrame;
    bool operator==(const TableKey&) const = default;
  };
  std::optional<TableKey> built_;
  bool reused_ = false;
};

}  // namespace penumbra::raster
