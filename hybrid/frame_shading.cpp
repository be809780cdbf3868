// FrameContext's shading stage: one light's shading pass, or a frame of several lights shaded a
// batch at a time (ShadePass), the batch's traced lights traced in one dispatch first
// (traceWithLights) and their visibility and rays settled into the frame afterwards.
#include <algorithm>

#include "hybrid/frame_context.h"

namespace penumbra {

void FrameContext::recordShade(const vk::raii::CommandBuffer& cmd) {
  using Stage = vk::PipelineStageFlagBits2;
  using Access = vk::AccessFlagBits2;
  // after the passes that wrote the visibility (and the indirect light)
  gpu::memoryBarrier(cmd, Stage::eComputeShader | Stage::eAllTransfer,
                     Access::eShaderStorageWrite | Access::eTransferWrite, Stage::eComputeShader | Stage::eAllTransfer,
                     Access::eShaderStorageRead | Access::eTransferRead);
  timer_.begin(cmd, "shade");
  if (slot_.count == 1) {
    shade_.record(cmd, gbuffer_, frameBuffer_, visibility_, indirect_, color_, term_);
    shadeRecorded_ = true;
  } else {
    // A full batch is shaded first, here where it traces nothing (else shade() does, in a submission
    // of its own, so that its trace's counters are not this light's trace's).
    const glm::uvec4 rect = lightRect();
    const bool fits = shade_.fits(rect);
    if (fits || !shade_.batchTraces()) {
      if (!fits) {
        shade_.prepareBatch(settings_.width, settings_.height);
        shade_.recordBatch(cmd, gbuffer_, frameBuffer_, color_, false);
      }
      shade_.recordLight(cmd, visibility_, frameData_.light, rect, slot_.index);
      joinedBatch_ = true;
      const bool last = slot_.order + 1 == slot_.count;
      if (last && !shade_.batchTraces()) {
        gpu::memoryBarrier(cmd, Stage::eAllTransfer, Access::eTransferWrite, Stage::eComputeShader,
                           Access::eShaderStorageRead);
        shade_.prepareBatch(settings_.width, settings_.height);
        shade_.recordBatch(cmd, gbuffer_, frameBuffer_, color_, true);
      }
      shadeRecorded_ = !last || !shade_.batchTraces();
    }
  }
  timer_.end(cmd);
}

void FrameContext::shade(FrameStats& stats) {
  if (shadeRecorded_) return;
  if (slot_.count == 1) {
    context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { recordShade(cmd); });
    return;
  }
  if (!joinedBatch_) {
    const glm::uvec4 rect = lightRect();
    if (!shade_.fits(rect)) {
      shadeBatch(false, stats);
      keepTracedLights();  // this light and the next batch write the batch buffer before the settling
    }
    if (!tracedWithLights_) {
      context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { recordShade(cmd); });
    } else if (rect.z > rect.x && rect.w > rect.y) {
      shade_.addTracedLight(frameData_.light, rect, slot_.index);
    } else {  // it reaches no pixel
      tracedLights_.push_back({{slot_.index, rect, 0, 0}, std::vector<float>{}});
    }
    joinedBatch_ = true;
  }
  if (!shadeRecorded_ && slot_.order + 1 == slot_.count) shadeBatch(true, stats);
  shadeRecorded_ = true;
}

bool FrameContext::tracesWithLights(const ShadowTracer& tracer) const {
  return settings_.oneLightsTrace && slot_.count > 1 && term_ == Term::Shadow && tracer.onDevice() &&
         !settings_.simulateBandwidth && frameData_.blockers == glm::uvec2(0u);
}

void FrameContext::traceWithLights(ShadowTracer& tracer, FrameStats& stats) {
  if (lightsTracer_ && lightsTracer_ != &tracer) throw std::logic_error("a frame's lights are traced by one tracer");
  lightsTracer_ = &tracer;
  if (!gbufferRecorded_) {  // the frame's first light
    context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { recordGBuffer(cmd); });
    gbufferRecorded_ = true;
  }
  frameData_.traceInPlace = 1u;  // every covered pixel of its rectangle (readBack)
  tracedWithLights_ = true;
  stats.tracer = tracer.name();
}

void FrameContext::shadeBatch(bool last, FrameStats& stats) {
  const bool traces = shade_.batchTraces();
  const ShadePass::BatchLists lists = shade_.prepareBatch(settings_.width, settings_.height);
  std::optional<TraceJob> job;
  if (traces) {  // its traced lights' trace: every pixel of their tiles, each to its tile's lights
    shared::FrameData data = frameData_;
    data.traceInPlace = 1u;
    data.spp = methodSpp_;  // each light takes as many of them as it needs
    data.blockers = glm::uvec2(0u);
    data.lightRectMin = glm::uvec2(lists.traced);
    data.lightRectMax = glm::uvec2(lists.traced.z, lists.traced.w);
    data.traceLights = gpu::addressHalves(lists.lists.lights);
    data.traceTiles = gpu::addressHalves(lists.lists.tiles);
    data.traceTilesX = lists.tilesX;
    lightsFrame_.upload(std::span<const shared::FrameData>(&data, 1));
    const shared::TraceCount count = inPlaceCount(lists.traced);
    lightsCount_.upload(std::span<const shared::TraceCount>(&count, 1));
    job.emplace(TraceJob{compact_.points(), lightsCount_, lightsFrame_, shade_.batchVisibility(),
                         gbuffer_.position().view(), gbuffer_.normal().view()});
  }
  context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
    if (job) {
      timer_.begin(cmd, "trace");
      lightsTracer_->record(cmd, *job);
      timer_.end(cmd);
    }
    timer_.begin(cmd, "shade");
    shade_.recordBatch(cmd, gbuffer_, frameBuffer_, color_, last);
    timer_.end(cmd);
  });
  if (!job) return;
  const TraceReport report = lightsTracer_->finish(*job);
  auto add = [](std::optional<std::uint64_t>& to, const std::optional<std::uint64_t>& count) {
    if (count) to = to.value_or(0) + *count;
  };
  add(stats.nodeVisits, report.nodeVisits);  // the batch's lights' traversal, counted where it ran
  add(stats.triangleTests, report.triangleTests);
  const std::vector<ShadePass::TracedLight> traced = shade_.tracedLights();
  const auto passes = timer_.read();
  const auto trace = std::find_if(passes.rbegin(), passes.rend(), [](const auto& p) { return p.first == "trace"; });
  std::uint64_t rays = 0;
  for (const ShadePass::TracedLight& light : traced) rays += light.rays;
  for (const ShadePass::TracedLight& light : traced) {
    tracedLights_.push_back({light, std::nullopt});
    const double share = rays ? double(light.rays) / double(rays) : 1.0 / double(traced.size());
    if (trace != passes.rend()) joinedTraceMs_[light.index] = trace->second * share;
  }
}

std::optional<double> FrameContext::joinedTraceMs(std::uint32_t light) const {
  const auto it = joinedTraceMs_.find(light);
  return it == joinedTraceMs_.end() ? std::nullopt : std::optional<double>(it->second);
}

namespace {
std::size_t rectArea(const glm::uvec4& r) { return r.z > r.x && r.w > r.y ? std::size_t(r.z - r.x) * (r.w - r.y) : 0; }
}  // namespace

void FrameContext::keepTracedLights() {
  const auto* batch = static_cast<const float*>(shade_.batchVisibility().data());
  for (TracedLight& traced : tracedLights_) {
    if (!traced.kept)
      traced.kept.emplace(batch + traced.light.offset, batch + traced.light.offset + rectArea(traced.light.rect));
  }
}

void FrameContext::settleTracedLights(std::vector<Frame>& frames) {
  for (const TracedLight& traced : tracedLights_) {
    const ShadePass::TracedLight& light = traced.light;
    Frame& frame = frames.at(light.index);
    frame.stats.raysTraced = light.rays;
    if (std::find(withoutBuffers_.begin(), withoutBuffers_.end(), light.index) != withoutBuffers_.end()) continue;
    frame.visibility.assign(std::size_t(settings_.width) * settings_.height, 0.0f);
    const float* rows =
        traced.kept ? traced.kept->data() : static_cast<const float*>(shade_.batchVisibility().data()) + light.offset;
    const glm::uvec4& r = light.rect;
    for (std::uint32_t y = r.y; y < r.w && rectArea(r) > 0; ++y) {
      const float* row = rows + std::size_t(y - r.y) * (r.z - r.x);
      std::copy(row, row + (r.z - r.x), frame.visibility.begin() + std::ptrdiff_t(y) * settings_.width + r.x);
    }
  }
  tracedLights_.clear();
}

}  // namespace penumbra
