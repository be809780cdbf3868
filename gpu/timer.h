// Per-pass GPU times from timestamp queries, in the order the passes were recorded.
//
// Two modes, because a CPU driver does not run a command buffer the way a GPU does:
// - Timestamps: a timestamp at each pass boundary and nothing else. The mode for a real GPU, whose
//   queue writes an ALL_COMMANDS timestamp once the work recorded before it is done.
// - Fenced: each timestamp between two full pipeline barriers. lavapipe (Mesa's CPU driver) replays
//   a command buffer on llvmpipe, where a timestamp is not taken where it was recorded: it is binned
//   into the current scene like a draw and taken when that scene is rasterized, at the next flush
//   (the next barrier, timestamp or the end of the submission), while a dispatch runs to completion
//   the moment it is replayed. So the stamp in front of a compute pass was taken after the pass had
//   run: the pass read ~0 and its time fell between two rows (courtyard 1024^2, Mesa 25: sm's
//   "lookup" and srt's "classify" ~0.3 ms, the rows adding up to 60-72% of the frame; Mesa 22.3:
//   "shade" ~0.1 ms, 84-89%); with TOP_OF_PIPE stamps it lands in the row before instead. A barrier
//   after the stamp (lavapipe: flush and wait) makes the stamp be taken there and then; the one
//   before it makes all earlier work, binned draws included, finish first. On lavapipe the two cost a
//   flush of an empty scene each (well under 0.1 ms a pass); a GPU would lose overlap between passes.
// The default is Fenced on a CPU device (lavapipe, any Mesa version) and Timestamps elsewhere;
// PENUMBRA_GPU_TIMER=timestamps|fenced overrides it (to compare the two on one driver).
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gpu/context.h"

namespace penumbra::gpu {

enum class TimerMode { Timestamps, Fenced };

const char* toString(TimerMode mode);
// The mode a GpuTimer on `context` uses when none is given: PENUMBRA_GPU_TIMER when set (throws on
// an unknown value), else Fenced on a CPU device and Timestamps on a GPU.
TimerMode defaultTimerMode(const Context& context);

class GpuTimer {
 public:
  explicit GpuTimer(const Context& context, std::uint32_t maxPasses = 32, std::optional<TimerMode> mode = std::nullopt);
  TimerMode mode() const { return mode_; }
  void reset();  // host-side query reset; call before recording a frame
  // Outside a render pass (the Fenced mode records pipeline barriers).
  void begin(const vk::raii::CommandBuffer& cmd, const std::string& pass);
  void end(const vk::raii::CommandBuffer& cmd);
  // After the submission completed: (pass, milliseconds) in recording order.
  std::vector<std::pair<std::string, double>> read() const;
  std::size_t passCount() const { return passes_.size(); }  // passes recorded since reset()

 private:
  void stamp(const vk::raii::CommandBuffer& cmd, std::uint32_t query) const;

  const Context& context_;
  std::uint32_t maxPasses_;
  TimerMode mode_;
  vk::raii::QueryPool pool_;
  std::vector<std::string> passes_;
  bool open_ = false;
};

}  // namespace penumbra::gpu
