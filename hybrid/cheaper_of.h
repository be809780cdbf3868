// Of two ways to the same result, the one its own timings say is cheaper on this device, scene and
// view (--tile-test auto: the penumbra mask with or without its tile test, FrameContext::classify).
// The first take warms and its time is dropped (on lavapipe a pass's first run also pays the first
// touch of its buffers: +35% at 1024^2); the next two time each way once; from then on it takes
// the cheaper by their last times, and every kRemeasure-th take the other, as views and content
// change.
#pragma once
#include <array>
#include <cstdint>
#include <optional>

namespace penumbra {

class CheaperOf {
 public:
  static constexpr std::uint64_t kRemeasure = 32;

  // The way of this take: false or true (the warming take true; then whichever is not timed yet).
  bool take() {
    if (takes_++ == 0) return last_ = true;
    if (!ms_[0] || !ms_[1]) return last_ = ms_[0].has_value();
    last_ = *ms_[1] <= *ms_[0];
    if (takes_ % kRemeasure == 0) last_ = !last_;
    return last_;
  }
  // The time of the last take's way (dropped for the first take).
  void timed(double ms) {
    if (takes_ > 1) ms_[last_] = ms;
  }
  std::optional<double> ms(bool way) const { return ms_[way]; }

 private:
  std::array<std::optional<double>, 2> ms_;  // each way's last time
  std::uint64_t takes_ = 0;
  bool last_ = true;
};

}  // namespace penumbra
