#include "gpu/timer.h"

#include <cstdlib>
#include <stdexcept>

namespace penumbra::gpu {
namespace {

// Every earlier command finishes (and its writes are visible) before any later one starts.
void fullBarrier(const vk::raii::CommandBuffer& cmd) {
  const vk::MemoryBarrier2 barrier{.srcStageMask = vk::PipelineStageFlagBits2::eAllCommands,
                                   .srcAccessMask = vk::AccessFlagBits2::eMemoryWrite,
                                   .dstStageMask = vk::PipelineStageFlagBits2::eAllCommands,
                                   .dstAccessMask = vk::AccessFlagBits2::eMemoryRead | vk::AccessFlagBits2::eMemoryWrite};
  cmd.pipelineBarrier2({.memoryBarrierCount = 1, .pMemoryBarriers = &barrier});
}

}  // namespace

const char* toString(TimerMode mode) { return mode == TimerMode::Fenced ? "fenced" : "timestamps"; }

TimerMode defaultTimerMode(const Context& context) {
  if (const char* env = std::getenv("PENUMBRA_GPU_TIMER"); env && *env) {
    const std::string value = env;
    if (value == "timestamps") return TimerMode::Timestamps;
    if (value == "fenced") return TimerMode::Fenced;
    throw std::runtime_error("PENUMBRA_GPU_TIMER='" + value + "' is not a timer mode; use timestamps or fenced (or unset it)");
  }
  return context.physicalDevice().getProperties().deviceType == vk::PhysicalDeviceType::eCpu ? TimerMode::Fenced
                                                                                            : TimerMode::Timestamps;
}

GpuTimer::GpuTimer(const Context& context, std::uint32_t maxPasses, std::optional<TimerMode> mode)
    : context_(context),
      maxPasses_(maxPasses),
      mode_(mode ? *mode : defaultTimerMode(context)),
      pool_(context.device(), {.queryType = vk::QueryType::eTimestamp, .queryCount = 2 * maxPasses}) {
  reset();
}

void GpuTimer::reset() {
  pool_.reset(0, 2 * maxPasses_);
  passes_.clear();
  open_ = false;
}

void GpuTimer::stamp(const vk::raii::CommandBuffer& cmd, std::uint32_t query) const {
  if (mode_ == TimerMode::Fenced) fullBarrier(cmd);  // the work before has finished ...
  cmd.writeTimestamp2(vk::PipelineStageFlagBits2::eAllCommands, *pool_, query);
  if (mode_ == TimerMode::Fenced) fullBarrier(cmd);  // ... and the stamp is taken before the work after starts
}

void GpuTimer::begin(const vk::raii::CommandBuffer& cmd, const std::string& pass) {
  if (open_ || passes_.size() >= maxPasses_) throw std::logic_error("GpuTimer: unbalanced begin or too many passes");
  stamp(cmd, std::uint32_t(2 * passes_.size()));
  passes_.push_back(pass);
  open_ = true;
}

void GpuTimer::end(const vk::raii::CommandBuffer& cmd) {
  if (!open_) throw std::logic_error("GpuTimer: end without begin");
  stamp(cmd, std::uint32_t(2 * passes_.size() - 1));
  open_ = false;
}

std::vector<std::pair<std::string, double>> GpuTimer::read() const {
  std::vector<std::pair<std::string, double>> out;
  if (passes_.empty()) return out;
  const auto [result, stamps] = pool_.getResults<std::uint64_t>(0, std::uint32_t(2 * passes_.size()),
                                                                2 * passes_.size() * sizeof(std::uint64_t), sizeof(std::uint64_t),
                                                                vk::QueryResultFlagBits::e64 | vk::QueryResultFlagBits::eWait);
  if (result != vk::Result::eSuccess) throw std::runtime_error("GpuTimer: timestamp results not available");
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    out.emplace_back(passes_[i], double(stamps[2 * i + 1] - stamps[2 * i]) * context_.timestampPeriodNs() * 1e-6);
  }
  return out;
}

}  // namespace penumbra::gpu
