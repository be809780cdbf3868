// PIP classification fused with the shadow-map lookup (see shaders/pip_classify.comp): writes the
// sm answer for every pixel, which pixels may be wrong (trace flags, PIP_* bits) and, for hard
// shadows, how far their shadow rays need to go; optionally appends those pixels to the trace list.
#pragma once
#include "gpu/pipeline.h"
#include "raster/depth_pyramid_pass.h"
#include "raster/gbuffer_pass.h"
#include "raster/shadow_map_pass.h"
#include "core/options.h"
#include "shared/pip.h"

namespace penumbra::raster {

// Area lights, maps of one face: whether the penumbra mask's search runs once per tile first
// (PipPush::tileTest). Auto: with or without it, whichever its own timings say is cheaper
// (FrameContext::classify).
enum class TileTest { Off, On, Auto };

struct PipSettings {
  float deltaFraction = 0.002f;   // depth-edge threshold as a fraction of the light's depth range
  float marginTexels = 1.0f;      // receiver depth interval widened by this many texel sizes
  bool thinPass = true;           // use the thin-triangle mask
  bool rayIntervals = false;      // bound hard-shadow rays by the neighbourhood's blocker depth
  std::uint32_t penumbraMaps = 1; // area lights: 1 = the centre's map, 5 = also the four corners' maps
  bool appendList = true;         // the classification writes the trace list itself (else the compaction
                                  // pass makes it from the flags, as it must when corner maps add flags)
  TileTest tileTest = TileTest::Auto;  // area lights: the penumbra mask's tile test first (TileTest)
  // Area lights: per tile, classify its pixels or trace them all, whichever the frame's cost model
  // predicts is cheaper (PipPush::tileTraceBelow; FrameContext::reportTileChoice). The library's default
  // is the paper's per-pixel classification everywhere; the command line's, the choice.
  bool tileChoice = false;
  // Tests: the tile choice's threshold (PipPush::tileTraceBelow) fixed, instead of the cost model's.
  std::uint32_t tileTraceBelow = 0;
  bool explain = false;  // write why each unflagged pixel was left out (PIP_WHY_*; area lights: PIP_MASK_*)
};

// The command line's options of the classification (--pip-delta, --ray-intervals, ...).
const Options<PipSettings>& pipOptions();

// Per-pixel outputs the classification writes and compaction reads.
struct PipBuffers {
  const gpu::Buffer& visibility;    // float: sm answer (tracers overwrite PIP pixels later)
  const gpu::Buffer& smVisibility;  // float: sm answer, kept for pip_miss_fraction
  const gpu::Buffer& traceFlags;    // uint: PIP_* bits, 0 = keep the sm answer
  const gpu::Buffer& rayMax;        // float: shadow-ray interval end, 0 = to the light
  // The count of the trace list that PipPush::appendList fills (TraceCount; the caller empties it).
  // The list itself is written through frame's FrameData::tracePoints, only where the flags are
  // nonzero, like smVisibility and rayMax.
  const gpu::Buffer& count;
  const gpu::Buffer& why;  // uint: PIP_WHY_* per pixel, written where explained (zeroed first)
  // uint per tile of PIP_MASK_TILE_SIZE^2 pixels: PIP_TILE_*, written where PipPush::tileTest.
  const gpu::Buffer& maskTiles;
  // uint per tile, where PipPush::tileTraceBelow (the tile choice): the last frame's counts
  // (PIP_TILE_COVERED), read, and this frame's, zeroed and written (transfer destination).
  const gpu::Buffer& tileDoubtLast;
  const gpu::Buffer& tileDoubt;
};

class PipClassifyPass {
 public:
  explicit PipClassifyPass(const gpu::Context& context);
  // thin: the thin-triangle mask's pass, or nullptr when the thin pass is off; explain: write `why`
  // (PipSettings::explain). Where push.tileTest, recordTileTest goes first, with the same arguments.
  void record(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const ShadowMapPass& shadowMap,
              const ThinTrianglePass* thin, const DepthPyramidPass& pyramid, const gpu::Buffer& frame,
              const PipBuffers& out, shared::PipPush push, bool explain) const;
  // The penumbra mask's tile test (maskTile in shaders/pip_tiles.glsl; one invocation per PIP_MASK_TILE_SIZE^2
  // tile of pixels): out.maskTiles.
  void recordTileTest(const vk::raii::CommandBuffer& cmd, const GBufferPass& gbuffer, const ShadowMapPass& shadowMap,
                      const ThinTrianglePass* thin, const DepthPyramidPass& pyramid, const gpu::Buffer& frame,
                      const PipBuffers& out, shared::PipPush push, bool explain) const;

  // The push constants for `settings` on this frame's shadow map.
  static shared::PipPush pushFor(const PipSettings& settings, const shared::ShadowMapInfo& info, bool thinMaskBound,
                                 float sceneRadius);

 private:
  // The push constants' addresses and levels, and every binding, for either dispatch.
  static void complete(gpu::Descriptors& descriptors, shared::PipPush& push, const GBufferPass& gbuffer,
                       const ShadowMapPass& shadowMap, const ThinTrianglePass* thin, const DepthPyramidPass& pyramid,
                       const gpu::Buffer& frame, const PipBuffers& out);

  gpu::SpecializedComputePipeline pipeline_;  // on texelReads()
};

}  // namespace penumbra::raster
