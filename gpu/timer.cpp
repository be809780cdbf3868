#include "gpu/timer.h"

#include <stdexcept>

namespace penumbra::gpu {

GpuTimer::GpuTimer(const Context& context, std::uint32_t maxPasses)
    : context_(context),
      maxPasses_(maxPasses),
      pool_(context.device(), {.queryType = vk::QueryType::eTimestamp, .queryCount = 2 * maxPasses}) {
  reset();
}

void GpuTimer::reset() {
  pool_.reset(0, 2 * maxPasses_);
  passes_.clear();
  open_ = false;
}

void GpuTimer::begin(const vk::raii::CommandBuffer& cmd, const std::string& pass) {
  if (open_ || passes_.size() >= maxPasses_) throw std::logic_error("GpuTimer: unbalanced begin or too many passes");
  cmd.writeTimestamp2(vk::PipelineStageFlagBits2::eAllCommands, *pool_, std::uint32_t(2 * passes_.size()));
  passes_.push_back(pass);
  open_ = true;
}

void GpuTimer::end(const vk::raii::CommandBuffer& cmd) {
  if (!open_) throw std::logic_error("GpuTimer: end without begin");
  cmd.writeTimestamp2(vk::PipelineStageFlagBits2::eAllCommands, *pool_, std::uint32_t(2 * passes_.size() - 1));
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
