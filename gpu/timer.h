// Per-pass GPU times from timestamp queries, in the order the passes were recorded.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "gpu/context.h"

namespace penumbra::gpu {

class GpuTimer {
 public:
  explicit GpuTimer(const Context& context, std::uint32_t maxPasses = 32);
  void reset();  // host-side query reset; call before recording a frame
  void begin(const vk::raii::CommandBuffer& cmd, const std::string& pass);
  void end(const vk::raii::CommandBuffer& cmd);
  // After the submission completed: (pass, milliseconds) in recording order.
  std::vector<std::pair<std::string, double>> read() const;

 private:
  const Context& context_;
  std::uint32_t maxPasses_;
  vk::raii::QueryPool pool_;
  std::vector<std::string> passes_;
  bool open_ = false;
};

}  // namespace penumbra::gpu
