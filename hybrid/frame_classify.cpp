// FrameContext's classification (TraceList::Doubtful, recordClassify): the thin-triangle mask, the
// edge pyramid, the penumbra mask's tile test (with --tile-test auto, its choice per light) and the
// PIP classification with the tile choice, then what readBack reports of the tile test and the
// tile choice.
#include <algorithm>
#include <cmath>
#include <cstdio>
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
  // The tile choice; not where explained, which wants every pixel's own rules
  tileChoice_ = nullptr;
  if (settings_.pip.tileChoice && shared::isAreaLight(frameData_.light) && !settings_.pip.explain) {
    tileChoice_ = &tileChoices_.try_emplace(slot_.index, context_, maskTiles_.size()).first->second;
    push.tileTraceBelow = settings_.pip.tileTraceBelow != 0u ? settings_.pip.tileTraceBelow : tileChoice_->traceBelow;
    push.tilePhase = tileChoice_->frames;
    stats.memoryBytes["tile_choice"] = 2 * maskTiles_.size();
  }
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
  const raster::PipBuffers out{visibility_,
                               smVisibility_,
                               traceFlags_,
                               rayMax_,
                               compact_.count(),
                               why_,
                               maskTiles_,
                               tileChoice_ ? tileChoice_->last : maskTiles_,
                               tileChoice_ ? tileChoice_->next : maskTiles_};
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

FrameContext::TileChoice::TileChoice(const gpu::Context& context, vk::DeviceSize bytes)
    : last(context, bytes, vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
           "tile choice counts"),
      next(context, bytes, vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst,
           "tile choice counts") {
  std::fill_n(static_cast<std::uint8_t*>(last.data()), bytes, std::uint8_t(0));  // no tile known yet
}

// The cost model: tracing a tile whole costs the rays of its pixels the classification would have
// left alone and saves the tile's classification, so a tile goes whole where fewer of its covered
// pixels than (time per classified tile) / (time per traced pixel) were unflagged, plus the tiles
// found wholly doubtful, which cost no ray more. Both times are this light's last frame's on this
// device (its last classification's and its last trace's, the paper's path's in a frame that ran both).
void FrameContext::reportTileChoice(const std::vector<std::pair<std::string, double>>& passes, FrameStats& stats,
                                    Frame& frame) {
  if (!tileChoice_) return;
  TileChoice& c = *tileChoice_;
  tileChoice_ = nullptr;
  const auto* counts = static_cast<const std::uint32_t*>(c.next.data());
  const std::size_t tiles = c.next.size() / sizeof(std::uint32_t);
  std::uint64_t classified = 0, whole = 0;
  for (std::size_t i = 0; i < tiles; ++i) {
    whole += (counts[i] & PIP_TILE_TRACED) != 0u;
    classified += counts[i] >= PIP_TILE_COVERED && (counts[i] & PIP_TILE_TRACED) == 0u;
  }
  stats.counts["tiles_traced_whole"] = whole;
  stats.counts["tiles_classified"] = classified;
  if (slot_.buffers) {  // the overlay: tiles traced whole, else the tile test's verdicts or a search each
    if (frame.maskTiles.empty()) frame.maskTiles.assign(tiles, std::uint8_t(PIP_TILE_NONE));
    for (std::size_t i = 0; i < tiles; ++i) {
      if (counts[i] & PIP_TILE_TRACED) {
        frame.maskTiles[i] = PIP_TILE_TRACE;
      } else if (!maskTilesTested_ && counts[i] >= PIP_TILE_COVERED) {
        frame.maskTiles[i] = PIP_TILE_SEARCH;
      }
    }
  }
  // The frame's last of each pass: its paper's path (run last where --srt-choice auto ran both). The
  // tile test counts with the classification: tiles traced whole skip it too. A CPU tracer's trace
  // (Embree) is its wall time, which no timestamp sees.
  double tileTestMs = 0.0, traceMs = lastTraceHostMs_;
  std::optional<double> classifyMs, deviceTraceMs;
  for (const auto& [pass, ms] : passes) {
    if (pass == "mask_tiles") tileTestMs = ms;
    if (pass == "classify") classifyMs = ms;
    if (pass == "trace") deviceTraceMs = ms;
  }
  traceMs += deviceTraceMs.value_or(0.0);
  const std::uint64_t pixels = stats.pipPixels.value_or(0);
  if (classifyMs && classified > 0 && pixels > 0 && traceMs > 0.0) {
    const double perTile = (*classifyMs + tileTestMs) / double(classified), perPixel = traceMs / double(pixels);
    const double below = 1.0 + std::floor(perTile / perPixel);
    c.traceBelow = std::uint32_t(std::min(below, double(PIP_MASK_TILE_SIZE * PIP_MASK_TILE_SIZE + 1)));
    char note[320];
    std::snprintf(note, sizeof(note),
                  "the tile choice traced %llu of %llu tiles whole (--tile-choice on): classifying took %.3f ms for "
                  "%llu tiles, the trace %.3f ms for %llu pixels, so a tile with fewer than %u unflagged pixels goes "
                  "whole next",
                  (unsigned long long)whole, (unsigned long long)(whole + classified), *classifyMs + tileTestMs,
                  (unsigned long long)classified, traceMs, (unsigned long long)pixels, c.traceBelow);
    stats.notes.push_back(note);
  }
  std::swap(c.last, c.next);
  ++c.frames;
}

}  // namespace penumbra
