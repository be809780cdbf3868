#include "hybrid/frame_context.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "core/gpu_light.h"
#include "core/units.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"
#include "shared/compact.h"
#include "shared/trace.h"

namespace penumbra {
namespace {

vk::DeviceSize pixels(const RenderSettings& s) { return vk::DeviceSize(s.width) * s.height; }
// The penumbra mask's tile test's tiles (PIP_MASK_TILE_SIZE^2 pixels each).
vk::DeviceSize maskTiles(const RenderSettings& s) {
  return vk::DeviceSize((s.width + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE) *
         ((s.height + PIP_MASK_TILE_SIZE - 1) / PIP_MASK_TILE_SIZE);
}

// Settings with the shadow maps' read path resolved for this device, so every map made from them
// (centre, corners, msm) tells its shaders the same.
RenderSettings resolved(const gpu::Context& context, RenderSettings s) {
  using Reads = raster::ShadowMapSettings::Reads;
  if (s.shadowMap.reads == Reads::Auto) s.shadowMap.reads = raster::bufferReads(context, s.shadowMap) ? Reads::Buffer : Reads::Texture;
  return s;
}

// One box per moving mesh (Mesh::dynamic), in the scene's order.
std::vector<Bounds> movingMeshBounds(const Scene& scene) {
  std::vector<Bounds> boxes;
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.dynamic) continue;
    Bounds& box = boxes.emplace_back();
    for (const glm::vec3& p : mesh.positions) box.extend(p);
  }
  return boxes;
}

}  // namespace

FrameContext::FrameContext(const gpu::Context& context, const Scene& scene, const RenderSettings& settings)
    : context_(context),
      scene_(scene),
      settings_(resolved(context, settings)),
      bounds_(scene.bounds()),
      geometry_(context, scene),
      gbuffer_(context, scene, settings.width, settings.height),
      lookup_(context),
      shade_(context),
      classify_(context),
      compact_(context, settings.width, settings.height),
      lightFit_(context),
      lightsFrame_(context, sizeof(shared::FrameData), vk::BufferUsageFlagBits::eStorageBuffer, "lights trace frame"),
      lightsCount_(context, sizeof(shared::TraceCount),
                   vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eIndirectBuffer,
                   "lights trace count"),
      frameBuffer_(context, sizeof(shared::FrameData), vk::BufferUsageFlagBits::eStorageBuffer, "frame data"),
      visibility_(context, pixels(settings) * sizeof(float),
                  vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst |
                      vk::BufferUsageFlagBits::eTransferSrc,
                  "visibility"),
      indirect_(context, pixels(settings) * sizeof(glm::vec4), vk::BufferUsageFlagBits::eStorageBuffer,
                "indirect light"),
      color_(context, pixels(settings) * 4, vk::BufferUsageFlagBits::eStorageBuffer, "shaded colour"),
      smVisibility_(context, pixels(settings) * sizeof(float), vk::BufferUsageFlagBits::eStorageBuffer,
                    "sm visibility"),
      traceFlags_(context, pixels(settings) * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eStorageBuffer,
                  "trace flags"),
      rayMax_(context, pixels(settings) * sizeof(float),
              vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst, "ray max"),
      why_(context, settings.pip.explain ? pixels(settings) * sizeof(std::uint32_t) : sizeof(std::uint32_t),
           vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eTransferDst, "pip why"),
      maskTiles_(context, maskTiles(settings) * sizeof(std::uint32_t), vk::BufferUsageFlagBits::eStorageBuffer,
                 "penumbra mask tiles"),
      blockers_(context, settings.denoise.mode != DenoiseMode::Off ? pixels(settings) * sizeof(float) : sizeof(float),
                vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eShaderDeviceAddress,
                "blocker distances"),
      timer_(context) {
  std::memset(blockers_.data(), 0, blockers_.size());  // 0: no blocker known (a CPU tracer never writes them)
  movingBounds_ = movingMeshBounds(scene);
}

FrameContext::~FrameContext() = default;

IndirectPass& FrameContext::indirectPass(FrameStats& stats) {
  if (!indirectPass_) indirectPass_ = std::make_unique<IndirectPass>(context_, scene_);
  stats.memoryBytes["scene_triangles"] = indirectPass_->bytes();
  return *indirectPass_;
}

const CandidateTracer& FrameContext::candidateTracer(FrameStats& stats) {
  if (!candidates_) {
    CandidateTracerSettings s;
    s.n = settings_.lineSpace.n;
    s.depth = settings_.indirect.bvhDepth;
    s.maxNormalDeviationDeg = settings_.indirect.maxDeviationDeg;
    s.budgetBytes = settings_.lineSpace.budgetBytes;
    candidates_ = std::make_unique<CandidateTracer>(context_, scene_, s);
  }
  const CandidateStats& ls = candidates_->lineSpace().stats;
  stats.setupMs["candidate_build"] = ls.buildMs + candidates_->bvh().stats.buildMs;
  stats.memoryBytes["bvh_ls"] = candidates_->bytes();
  char note[240];
  std::snprintf(note, sizeof(note),
                "candidate line space (N=%u, BVH depth %u): %llu line spaces, %.1f%% of shafts filled, %.1f MB sparse "
                "(dense %.1f MB), built in %.0f ms",
                ls.n, settings_.indirect.bvhDepth, (unsigned long long)ls.boxes, 100.0 * ls.filledFraction,
                double(ls.sparseBytes) / 1e6, double(ls.denseBytes) / 1e6, ls.buildMs);
  stats.notes.push_back(note);
  return *candidates_;
}

const LineSpaceTracer& FrameContext::ntreeTracer(FrameStats& stats) {
  if (!ntree_) {
    LineSpaceSettings s = settings_.lineSpace;
    s.shadows = LineSpaceSettings::Shadows::Exact;
    s.movingTracer = LineSpaceSettings::Moving::Bvh;  // the indirect kernel traces them on the BVH
    ntree_ = std::make_unique<LineSpaceTracer>(context_, scene_, s);
  }
  const LineSpaceStats& ls = ntree_->stats();
  stats.setupMs["ntree_build"] = ls.buildMs;
  stats.memoryBytes["ntree"] = ls.bytes;
  char note[240];
  std::snprintf(note, sizeof(note),
                "N-tree (N=%u, d=%u, exact): %llu subdivided nodes, %llu leaf cells, %llu triangle references, %.1f MB "
                "(leaf lists and triangles %.1f), built in %.0f ms",
                ls.n, ls.depth, (unsigned long long)ls.nodes, (unsigned long long)ls.leaves,
                (unsigned long long)ls.leafTriangleRefs, double(ls.bytes) / 1e6, double(ls.exactBytes()) / 1e6, ls.buildMs);
  stats.notes.push_back(note);
  return *ntree_;
}

const NTreeCandidateTracer& FrameContext::ntreeCandidateTracer(FrameStats& stats) {
  if (!ntreeLs_) {
    NTreeCandidateSettings s;
    s.lineSpace = settings_.lineSpace;
    const int depth = settings_.indirect.ntreeDepth;
    s.depth = depth < 0 ? NTreeCandidateSettings::kSecondToLast : std::uint32_t(depth);
    s.minTriangles = settings_.indirect.ntreeMinTriangles;
    s.maxNormalDeviationDeg = settings_.indirect.maxDeviationDeg;
    ntreeLs_ = std::make_unique<NTreeCandidateTracer>(context_, scene_, s);
  }
  const CandidateStats& cs = ntreeLs_->candidates().stats;
  const LineSpaceStats& ls = ntreeLs_->lineSpace().stats();
  stats.setupMs["ntree_ls_build"] = ntreeLs_->buildMs();
  stats.memoryBytes["ntree_ls"] = ntreeLs_->bytes();
  char note[320];
  std::snprintf(note, sizeof(note),
                "N-tree with candidate line spaces (N=%u, d=%u, D=%u, T=%u): %llu line spaces, %.1f%% of shafts filled, "
                "%.1f MB sparse (dense %.1f MB); binary line space %.1f MB; built in %.0f ms",
                ls.n, ls.depth, ntreeLs_->depth(), settings_.indirect.ntreeMinTriangles, (unsigned long long)cs.boxes,
                100.0 * cs.filledFraction, double(cs.sparseBytes) / 1e6, double(cs.denseBytes) / 1e6,
                double(ls.bytes) / 1e6, ntreeLs_->buildMs());
  stats.notes.push_back(note);
  if (ntreeLs_->placedShallower()) {
    stats.notes.push_back("ntree-ls: D = d - 1 would exceed the budget or the device's buffer limit; placed at D = " +
                          std::to_string(ntreeLs_->depth()) + " (--ntree-ls-depth)");
  }
  return *ntreeLs_;
}

const EmbreeTracer& FrameContext::embree(FrameStats& stats) { return static_cast<EmbreeTracer&>(tracer(stats, "embree")); }

ShadowTracer& FrameContext::tracer(FrameStats& stats, const std::string& name) {
  const std::string resolvedName = resolveTracer(context_, name.empty() ? settings_.tracer : name);
  const TracerEntry& entry = tracerEntry(resolvedName);  // InputError for unknown names
  auto it = tracers_.find(resolvedName);
  if (it == tracers_.end()) it = tracers_.emplace(resolvedName, entry.make(context_, scene_, settings_)).first;
  entry.report(*it->second, settings_, stats);
  return *it->second;
}

void FrameContext::sceneMoved() {
  ++sceneVersion_;
  geometry_.update(scene_);
  // What the move swept, for the maps of the lights it did not reach (lightPassesKey).
  std::vector<Bounds> now = movingMeshBounds(scene_);
  Move& move = moves_.emplace_back(Move{geometry_.version(), now});
  for (std::size_t i = 0; i < now.size() && i < movingBounds_.size(); ++i) {
    if (movingBounds_[i].empty()) continue;
    move.swept[i].extend(movingBounds_[i].lo);
    move.swept[i].extend(movingBounds_[i].hi);
  }
  constexpr std::size_t kMoves = 64;  // older moves count as having reached every map
  if (moves_.size() > kMoves) moves_.pop_front();
  movingBounds_ = std::move(now);
  if (indirectPass_) indirectPass_->update(scene_);
  candidates_.reset();  // one tree over every mesh: built again on next use
  // The built tracers refit (or rebuild) their dynamic BVHs; frames report the first one's update
  // by name (bvh before ls before rq; all hold the same tree over the same triangles), else the
  // N-trees'. A tracer that cannot refit (embree) is built again on next use.
  std::optional<BvhRefitReport> traced;
  for (auto it = tracers_.begin(); it != tracers_.end();) {
    const std::optional<BvhRefitReport> report = it->second->sceneMoved(scene_);
    if (!traced) traced = report;
    it = report ? std::next(it) : tracers_.erase(it);
  }
  if (ntreeLs_) {  // static line spaces stay; the moving BVHs refit
    const BvhRefitReport report = ntreeLs_->update(scene_);
    if (!traced) traced = report;
  }
  if (ntree_) {
    const BvhRefitReport report = ntree_->update(scene_);
    if (!traced) traced = report;
  }
  refit_.reset();
  if (traced) {
    refit_ = FrameStats::Refit{traced->ms, traced->sah, traced->builtSah, traced->growth, traced->rebuilt, traced->rebuilds};
  }
}

glm::uvec4 FrameContext::lightRect() const {
  if (frameData_.lightRectMax == glm::uvec2(0u)) return {0u, 0u, settings_.width, settings_.height};
  return {frameData_.lightRectMin, frameData_.lightRectMax};
}

TraceJob FrameContext::traceJob(const ShadowTracer& tracer, TraceList list) {
  const bool inPlace = list == TraceList::EveryCovered && tracer.onDevice() && !settings_.simulateBandwidth;
  if (frameData_.traceInPlace != (inPlace ? 1u : 0u)) {
    frameData_.traceInPlace = inPlace ? 1u : 0u;
    frameBuffer_.upload(std::span<const shared::FrameData>(&frameData_, 1));  // no submission is running
  }
  return {compact_.points(), compact_.count(), frameBuffer_, visibility_, gbuffer_.position().view(), gbuffer_.normal().view()};
}

void FrameContext::recordTraceCount(const vk::raii::CommandBuffer& cmd, const shared::TraceCount& count) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  gpu::memoryBarrier(cmd, Stage::eDrawIndirect | Stage::eComputeShader, Access::eIndirectCommandRead | Access::eShaderStorageRead,
                     Stage::eAllTransfer, Access::eTransferWrite);
  cmd.updateBuffer<shared::TraceCount>(compact_.count().handle(), 0, count);
  gpu::memoryBarrier(cmd, Stage::eAllTransfer, Access::eTransferWrite, Stage::eDrawIndirect | Stage::eComputeShader,
                     Access::eIndirectCommandRead | Access::eShaderStorageRead | Access::eShaderStorageWrite);
}

void FrameContext::finishTrace(ShadowTracer& tracer, const TraceJob& job, FrameStats& stats) {
  if (!frameData_.traceInPlace) {  // the list holds what one storage binding can: a frame that flags more is refused
    const std::uint64_t listed = job.count.download<shared::TraceCount>(1).front().count;
    const std::uint64_t capacity = job.points.size() / sizeof(shared::ShadingPoint);
    if (listed > capacity) {
      throw InputError(std::to_string(listed) + " pixels to trace, more than the trace list's " + std::to_string(capacity) +
                       " (one storage binding of this device); lower --res");
    }
    stats.pipPixels = listed;
  }
  const TraceReport report = tracer.finish(job);
  if (report.hostMs > 0.0) stats.addPass("trace", report.hostMs);
  lastTraceHostMs_ = report.hostMs;
  stats.tracer = tracer.name();
  stats.raysTraced = report.rays;
  stats.nodeVisits = report.nodeVisits;
  stats.triangleTests = report.triangleTests;
}

shared::TraceCount FrameContext::inPlaceCount(const glm::uvec4& rect) const {
  // Every tile's pixels of the rectangle (trace_points.glsl), in rows of as many workgroups as the
  // device dispatches (tracePointIndex).
  const std::uint32_t items = shared::compactItems(rect.z - rect.x, rect.w - rect.y);
  const std::uint32_t groups = (items + TRACE_GROUP_SIZE - 1) / TRACE_GROUP_SIZE;
  const std::uint32_t row =
      std::max(1u, std::min(groups, context_.physicalDevice().getProperties().limits.maxComputeWorkGroupCount[0]));
  return {items, row, (groups + row - 1) / row, 1};
}

void FrameContext::recordInPlaceCount(const vk::raii::CommandBuffer& cmd) {
  recordTraceCount(cmd, inPlaceCount(lightRect()));
}

void FrameContext::recordTraceList(const vk::raii::CommandBuffer& cmd, TraceList list, FrameStats& stats) {
  switch (list) {
    case TraceList::Doubtful:
      if (!classify(cmd, stats, true)) recordCompact(cmd, COMPACT_FLAGGED);
      break;
    case TraceList::Flagged:
      recordCompact(cmd, COMPACT_FLAGGED);
      break;
    case TraceList::EveryCovered:
      recordUnclassified(cmd);
      if (frameData_.traceInPlace) recordInPlaceCount(cmd);
      else recordCompact(cmd, COMPACT_ALL_COVERED);
      break;
  }
}

void FrameContext::recordCompact(const vk::raii::CommandBuffer& cmd, std::uint32_t mode) {
  timer_.begin(cmd, "compact");
  compact_.record(cmd, gbuffer_, traceFlags_, rayMax_, frameBuffer_, mode);
  timer_.end(cmd);
}

void FrameContext::recordUnclassified(const vk::raii::CommandBuffer& cmd) {
  // 1 where the trace leaves a pixel; 0 where the light's rectangle is less than the image: beyond
  // it the light reaches no pixel.
  const bool wholeImage = frameData_.lightRectMax == glm::uvec2(0u);
  cmd.fillBuffer(visibility_.handle(), 0, VK_WHOLE_SIZE, wholeImage ? 0x3f800000u : 0u);  // 1.0f or 0.0f
  // Rays go all the way to the light: the compaction lists that (an in-place trace reads no list).
  if (!frameData_.traceInPlace) cmd.fillBuffer(rayMax_.handle(), 0, VK_WHOLE_SIZE, 0u);
  const vk::MemoryBarrier2 barrier{.srcStageMask = vk::PipelineStageFlagBits2::eClear,
                                   .srcAccessMask = vk::AccessFlagBits2::eTransferWrite,
                                   .dstStageMask = vk::PipelineStageFlagBits2::eComputeShader,
                                   .dstAccessMask = vk::AccessFlagBits2::eShaderStorageRead | vk::AccessFlagBits2::eShaderStorageWrite};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &barrier});
}

void FrameContext::begin(const Camera& camera, const Light& light, const Method& method, std::uint32_t frame,
                         FrameStats& stats, LightSlot slot) {
  view_ = cameraMatrices(camera, bounds_, int(settings_.width), int(settings_.height));
  cameraPosition_ = camera.eye;
  frameData_ = {};
  slot_ = slot;
  term_ = method.term();
  shadeRecorded_ = false;
  joinedBatch_ = false;
  tracedWithLights_ = false;
  maps_ = nullptr;
  mapsPastBudget_ = false;
  tileTestTake_.reset();
  if (slot.order == 0) {
    lightsTracer_ = nullptr;
    tracedLights_.clear();
    withoutBuffers_.clear();
    if (slot.count > 1) shade_.beginLights(slot.count, settings_.width, settings_.height);
  }
  frameData_.light = toGpuLight(light, bounds_, settings_.rayEpsilon);
  frameData_.lightError = settings_.lightError;
  frameData_.light.sampleFrame = frame;
  frameData_.light.sharedPattern = settings_.sharedSamples || method.sharedSamplePattern() ? 1u : 0u;
  mapSettings_ = settings_.shadowMap;
  mapSettings_.resolution = mapResolution();
  frameData_.shadow = raster::makeShadowMapInfo(frameData_.light, bounds_, mapSettings_);
  if (frameData_.shadow.kind == SHADOW_CUBE) {  // its near plane out to the nearest geometry (depth precision)
    constexpr std::size_t kMaxClearances = 1024;
    const glm::vec3 at(frameData_.light.position);
    std::erase_if(clearances_, [&](const Clearance& c) { return c.sceneVersion != sceneVersion_; });
    auto known = std::find_if(clearances_.begin(), clearances_.end(), [&](const Clearance& c) { return c.at == at; });
    if (known == clearances_.end()) {
      if (clearances_.size() >= kMaxClearances) clearances_.clear();  // lights that move: do not grow without end
      known =
          clearances_.insert(clearances_.end(), Clearance{at, sceneVersion_, distanceToNearestTriangle(scene_, at)});
    }
    frameData_.shadow = raster::makeShadowMapInfo(frameData_.light, bounds_, mapSettings_, false, known->distance);
  }
  frameData_.cameraPosition = glm::vec4(camera.eye, 1.0f);
  frameData_.width = settings_.width;
  frameData_.height = settings_.height;
  methodSpp_ = method.samplesPerPixel(settings_);
  frameData_.spp = shared::lightSampleCount(frameData_.light, methodSpp_);
  frameData_.shadowFilter = method.shadowFilter(settings_);
  if (frameData_.light.range > 0.0f && frameData_.light.type != LIGHT_DIRECTIONAL) {
    glm::uvec4 rect = screenRect(view_, glm::vec3(frameData_.light.position), frameData_.light.range, settings_.width,
                                 settings_.height);
    if (rect.z <= rect.x || rect.w <= rect.y) rect = glm::uvec4(1u);  // empty (lightRectMax (0, 0) is the image)
    if (rect != glm::uvec4(0u, 0u, settings_.width, settings_.height)) {
      frameData_.lightRectMin = glm::uvec2(rect.x, rect.y);
      frameData_.lightRectMax = glm::uvec2(rect.z, rect.w);
    }
  }
  compact_.describeList(frameData_);
  if (settings_.denoise.mode != DenoiseMode::Off && shared::isAreaLight(frameData_.light))
    frameData_.blockers = gpu::addressHalves(blockers_);
  frameBuffer_.upload(std::span<const shared::FrameData>(&frameData_, 1));
  stats.samplesPerPixel = frameData_.spp;
  timer_.reset();
  maskTilesTested_ = false;
  tileChoice_ = nullptr;
  lastTraceHostMs_ = 0.0;
  gbufferRecorded_ = slot.order > 0;  // the frame's first light rendered it
  coveredRead_ = coveredRead_ && slot.order > 0;
}

bool FrameContext::lightReachesView(const Camera& camera, const Light& light) const {
  if (light.range <= 0.0f || light.type == LightType::Directional) return true;
  return sphereInView(cameraMatrices(camera, bounds_, int(settings_.width), int(settings_.height)), light.position,
                      light.range);
}

void FrameContext::fitLightToView(FrameStats& stats) {
  if (!settings_.fitLightToView || shared::isAreaLight(frameData_.light) || frameData_.shadow.faceCount != 1) return;
  context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    recordGBuffer(cmd);
    timer_.begin(cmd, "light_fit");
    lightFit_.record(cmd, gbuffer_, frameData_.shadow);
    timer_.end(cmd);
  });
  gbufferRecorded_ = true;
  // Margin: the 3x3 classification neighbourhood, the normal offset and a 5x5 PCF kernel stay on
  // the map. Zoom limit: beyond it texels would shrink below what the depth bias was tuned for.
  constexpr float kMarginTexels = 4.0f, kMaxZoom = 16.0f;
  const shared::ShadowMapInfo whole = frameData_.shadow;
  frameData_.shadow = raster::fitShadowMap(whole, lightFit_.bounds(), kMarginTexels, kMaxZoom);
  frameBuffer_.upload(std::span<const shared::FrameData>(&frameData_, 1));
  stats.lightMapZoom = whole.texelWorld / frameData_.shadow.texelWorld;
}

void FrameContext::recordGBuffer(const vk::raii::CommandBuffer& cmd) {
  if (gbufferRecorded_) return;
  coveredRead_ = false;
  timer_.begin(cmd, "gbuffer");
  gbuffer_.record(cmd, geometry_, view_, cameraPosition_);
  timer_.end(cmd);
}

Frame FrameContext::readBack(const Method& method, FrameStats stats) {
  const auto passes = timer_.read();
  for (const auto& [pass, ms] : passes) stats.addPass(pass, ms);
  reportTileTest(passes, method.classifies(), stats);
  if (stats.thinPass) stats.thinPass->thin = maps().thin->thinTriangles();
  Frame frame;
  frame.width = settings_.width;
  frame.height = settings_.height;
  if (!coveredRead_) {  // once per G-buffer: the frame's other lights share it
    context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { gbuffer_.recordReadback(cmd); });
    std::vector<glm::vec4> positions = gbuffer_.positions();
    covered_.resize(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) covered_[i] = positions[i].w != 0.0f;
    coveredRead_ = true;
    positions_.clear();
    normals_.clear();
    if (settings_.lightError > 0.0f) {
      positions_ = std::move(positions);
      normals_ = gbuffer_.normals();
    }
  }
  const bool last = slot_.order + 1 == slot_.count;
  if (slot_.buffers || last) frame.covered = covered_;  // the last light's is the frame's
  if (!slot_.buffers) withoutBuffers_.push_back(slot_.index);
  const std::size_t pixels = covered_.size();
  if (tracedWithLights_ || !slot_.buffers) {
    // none, or its batch's trace's (settleTracedLights)
  } else if (method.term() == Term::Shadow) {
    frame.visibility = visibility_.download<float>(pixels);
  } else {  // the frame's term: ao = 1 - occlusion, indirect = the mean of rgb
    const auto light = indirect_.download<glm::vec4>(pixels);
    frame.visibility.resize(light.size());
    for (std::size_t i = 0; i < light.size(); ++i) {
      frame.visibility[i] = method.term() == Term::Ao ? 1.0f - light[i].a : (light[i].r + light[i].g + light[i].b) / 3.0f;
    }
  }
  if (last) {
    frame.rgba = color_.download<std::uint8_t>(pixels * 4);
    if (slot_.count > 1) {
      stats.counts["shade_batches"] = shade_.batches();
      stats.memoryBytes["light_visibilities"] = shade_.batchBytes();
    }
  }
  const std::uint64_t covered = std::count(covered_.begin(), covered_.end(), std::uint8_t(1));
  if (frameData_.traceInPlace) {  // every covered pixel of the light's rectangle, read from the G-buffer
    const glm::uvec4 rect = lightRect();
    std::uint64_t traced = 0;
    for (std::uint32_t y = rect.y; y < rect.w; ++y) {
      traced += std::count(covered_.begin() + y * frame.width + rect.x, covered_.begin() + y * frame.width + rect.z,
                           std::uint8_t(1));
    }
    stats.pipPixels = traced;
  }
  if (settings_.lightError > 0.0f && (method.classifies() || frameData_.traceInPlace)) {
    // --light-error: the pixels where the light's shadow weighs less than it (an approximate answer
    // stands there: the map's, or unshadowed in a trace in place, which traced only the others);
    // beyond the light's rectangle its range reaches nothing: weight 0
    std::vector<float> weights(pixels, 0.0f);
    std::uint64_t slight = 0, untraced = 0;
    const glm::uvec4 rect = lightRect();
    for (std::uint32_t y = rect.y; y < rect.w; ++y) {
      for (std::size_t i = std::size_t(y) * frame.width + rect.x; i < std::size_t(y) * frame.width + rect.z; ++i) {
        if (!covered_[i]) continue;
        weights[i] = shared::shadowWeight(frameData_.light, glm::vec3(positions_[i]), glm::vec3(normals_[i]));
        if (weights[i] >= settings_.lightError) continue;
        slight += weights[i] > 0.0f;
        ++untraced;
      }
    }
    stats.counts["light_error_pixels"] = slight;
    if (frameData_.traceInPlace && stats.pipPixels) stats.pipPixels = *stats.pipPixels - untraced;
    if (slot_.buffers) frame.shadowWeight = std::move(weights);
  }
  if (stats.pipPixels) {
    stats.pipFraction = covered ? double(*stats.pipPixels) / double(covered) : 0.0;
    if (method.classifies() && shared::isAreaLight(frameData_.light) && *stats.pipFraction > 0.75) {
      stats.notes.push_back("the penumbra mask covers " + std::to_string(int(100.0 * *stats.pipFraction)) +
                            "% of covered pixels: srt traces nearly every pixel, i.e. costs frt plus the map passes");
    }
  }
  if (method.classifies() && slot_.buffers) {
    const auto flags = traceFlags_.download<std::uint32_t>(pixels);
    frame.pip.assign(flags.begin(), flags.end());
    // The classification stored the sm answer again only where it flagged (the trace overwrites
    // those); elsewhere the final visibility is it.
    frame.shadowMapVisibility = smVisibility_.download<float>(pixels);
    for (std::size_t i = 0; i < flags.size(); ++i) {
      if (flags[i] == 0u) frame.shadowMapVisibility[i] = frame.visibility[i];
    }
    if (settings_.pip.explain) {
      const auto why = why_.download<std::uint32_t>(pixels);
      frame.pipWhy.assign(why.begin(), why.end());
    }
    if (maskTilesTested_) {
      const auto* tiles = static_cast<const std::uint32_t*>(maskTiles_.data());
      frame.maskTiles.assign(tiles, tiles + maskTiles_.size() / sizeof(std::uint32_t));
    }
  }

  if (mapsPastBudget_) {
    stats.notes.push_back("its maps are past --light-maps-memory " + std::to_string(settings_.lightMapsMiB) +
                          " MiB (other lights keep theirs): rendered again every frame");
  }
  reportTileChoice(passes, stats, frame);
  stats.refit = refit_;
  stats.memoryBytes["scene_geometry"] = geometry_.bytes();
  stats.memoryBytes["gbuffer"] = gbuffer_.bytes();
  if (stats.pipPixels && !frameData_.traceInPlace) stats.memoryBytes["ray_list"] = compact_.bytes();
  frame.stats = std::move(stats);
  return frame;
}

}  // namespace penumbra
