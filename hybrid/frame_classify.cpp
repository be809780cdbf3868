// FrameContext's classification (TraceList::Doubtful, recordClassify): the thin-triangle mask, the
// edge pyramid, the penumbra mask's tile test (with --tile-test auto, its choice per light) and the
// PIP classification, then what readBack reports of the tile test.
#include <span>

#include "hybrid/frame_context.h"

namespace penumbra {

bool FrameContext::classify(const vk::raii::CommandBuffer& cmd, FrameStats& stats, bool appendList) {
  const bool thin = settings_.pip.thinPass;
  if (thin) {
    if (!maps().thin) {
      maps().thin = std::make_unique<raster::ThinTrianglePass>(context_, mapSettings_, frameData_.shadow.faceCount,
                                                               settings_.thin);
    }
    stats.memoryBytes["thin_mask"] = maps().thin->bytes();
    timer_.begin(cmd, "thin_pass");
    maps().thin->record(cmd, geometry_, frameData_.shadow);
    timer_.end(cmd);
    stats.thinPass = FrameStats::ThinPass{.faces = frameData_.shadow.faceCount,
                                          .triangles = scene_.triangleCount(),
                                          .reused = maps().thin->selectionReused()};
  }
  LightMaps& m = maps();
  const raster::ThinTrianglePass* thinPass = thin ? m.thin.get() : nullptr;
  const bool cornerMaps = shared::isAreaLight(frameData_.light) && settings_.pip.penumbraMaps == 5;
  auto push = raster::PipClassifyPass::pushFor(settings_.pip, frameData_.shadow, thin, bounds_.radius());
  push.appendList = appendList && settings_.pip.appendList && !cornerMaps ? 1u : 0u;  // corner maps add flags after it
  push.tileTest = takesTileTest() ? 1u : 0u;
  maskTilesTested_ = push.tileTest != 0u;
  if (!m.pyramid) {
    m.pyramid =
        std::make_unique<raster::DepthPyramidPass>(context_, mapSettings_.resolution, frameData_.shadow.faceCount);
  }
  if (shared::isAreaLight(frameData_.light)) {  // the penumbra mask reads the pyramid; hard shadows do not
    stats.memoryBytes["depth_pyramid"] = m.pyramid->tiles().size();
    // Its inputs, the map and the thin mask, follow from the key (the thin pass keeps its own).
    const LightPassesKey key = lightPassesKey();
    if (settings_.reuseLightPasses && m.pyramidKey == key) {
      stats.reusedPasses.push_back("depth_pyramid");
    } else {
      timer_.begin(cmd, "depth_pyramid");
      m.pyramid->record(cmd, *m.shadowMap, thinPass, frameData_.shadow, push.deltaThreshold);
      timer_.end(cmd);
      m.pyramidKey = key;
    }
  }
  const raster::PipBuffers out{visibility_, smVisibility_, traceFlags_, rayMax_, compact_.count(), why_, maskTiles_};
  if (push.tileTest) {
    timer_.begin(cmd, "mask_tiles");
    classify_.recordTileTest(cmd, gbuffer_, *m.shadowMap, thinPass, *m.pyramid, frameBuffer_, out, push,
                             settings_.pip.explain);
    timer_.end(cmd);
  }
  timer_.begin(cmd, "classify");
  if (push.appendList) recordTraceCount(cmd, {0, 0, 1, 1});  // an empty list: workgroups add to count and groupsX
  classify_.record(cmd, gbuffer_, *m.shadowMap, thinPass, *m.pyramid, frameBuffer_, out, push, settings_.pip.explain);
  timer_.end(cmd);
  if (cornerMaps) {
    if (!cornerMaps_) cornerMaps_ = std::make_unique<raster::CornerMapsPass>(context_, settings_.shadowMap);
    timer_.begin(cmd, "corner_maps");
    cornerMaps_->record(cmd, geometry_, gbuffer_, classify_, frameData_, bounds_, out, settings_.pip);
    timer_.end(cmd);
    stats.memoryBytes["corner_maps"] = cornerMaps_->bytes();
  }
  return push.appendList != 0u;
}

// Area lights with a map of one face: --tile-test on or off, or auto's take for this light's frame
// (CheaperOf, once per frame; reportTileTest times it).
bool FrameContext::takesTileTest() {
  if (!shared::isAreaLight(frameData_.light) || frameData_.shadow.faceCount != 1) return false;
  if (settings_.pip.tileTest != raster::TileTest::Auto) return settings_.pip.tileTest == raster::TileTest::On;
  if (!tileTestTake_) tileTestTake_ = tileTestChoices_[slot_.index].take();
  return *tileTestTake_;
}

void FrameContext::reportTileTest(const std::vector<std::pair<std::string, double>>& passes, bool classified,
                                  FrameStats& stats) {
  if (tileTestTake_) {  // --tile-test auto: the classification's time with the frame's take
    double ms = 0.0;    // per classification of the frame (srt's --srt-choice auto may run two)
    int runs = 0;
    for (const auto& [pass, passMs] : passes) {
      runs += pass == "classify";
      if (pass == "classify" || pass == "mask_tiles") ms += passMs;
    }
    CheaperOf& choice = tileTestChoices_[slot_.index];
    if (runs > 0) choice.timed(ms / runs);
    auto last = [&](bool test) {
      const std::optional<double> t = choice.ms(test);
      return t ? std::to_string(*t) + " ms" : std::string("not yet timed");
    };
    stats.notes.push_back(std::string("the penumbra mask's tile test (--tile-test auto) ") +
                          (*tileTestTake_ ? "ran" : "did not run") + " in this frame; the classification last took " +
                          last(true) + " with it (its own pass included), " + last(false) + " without");
    tileTestTake_.reset();
  }
  if (!classified || !maskTilesTested_) return;
  std::uint64_t tested = 0, clear = 0;  // tiles with receivers, clear ones, counted in the mapped buffer
  const auto* tiles = static_cast<const std::uint32_t*>(maskTiles_.data());
  for (const std::uint32_t tile : std::span(tiles, maskTiles_.size() / sizeof(std::uint32_t))) {
    tested += tile != PIP_TILE_NONE;
    clear += tile == PIP_TILE_CLEAR;
  }
  stats.counts["mask_tiles"] = tested;
  stats.counts["mask_tiles_clear"] = clear;
}

}  // namespace penumbra
