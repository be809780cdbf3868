// Per-pass GPU timers attribute time to the pass that spent it. A small frame shaped like the
// renderer's (a raster pass, then compute passes in the same submission, then a compute pass in a
// second submission) is timed with every pass cheap, then with one pass made deliberately slow (a
// loop whose length comes from a push constant). The slow pass's row must grow by about what the
// frame's wall time grew by, and every other row must stay about where it was. lavapipe on Mesa 25
// failed this with bare timestamps: a compute pass after a render pass read ~0 and its time was
// lost between rows. Ratios only; the slow pass's cost is calibrated on this machine at run time.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "gpu/resources.h"
#include "gpu/timer.h"
#include "test_timer_spin_comp.h"
#include "test_timer_spin_frag.h"
#include "test_timer_spin_vert.h"

namespace penumbra::test {
namespace {

constexpr std::uint32_t kSize = 256;  // a 256x256 target; one invocation per pixel in the compute passes
constexpr std::uint32_t kCheap = 1;   // loop iterations of a cheap pass

struct Push {
  std::uint32_t iterations;
  std::uint32_t count;
};

gpu::Context& timerContext() {
  static gpu::Context context({.validate = true, .printMessages = true});
  return context;
}

// The four passes of the test frame and the loop length of each.
const std::array<std::string, 4> kPasses = {"draw", "spin_a", "spin_b", "spin_c"};
using Iterations = std::map<std::string, std::uint32_t>;

struct FrameTimes {
  double wallMs = 0.0;
  std::map<std::string, double> passMs;
};

class TimerFrame {
 public:
  explicit TimerFrame(gpu::Context& context)
      : context_(context),
        values_(context, vk::DeviceSize(kSize) * kSize * sizeof(float), vk::BufferUsageFlagBits::eStorageBuffer,
                "timer test values"),
        target_(context, {vk::Format::eR8G8B8A8Unorm, kSize, kSize, 1,
                          vk::ImageUsageFlagBits::eColorAttachment | vk::ImageUsageFlagBits::eSampled, "timer test target"}),
        spin_(context, test_timer_spin_comp, kBindings, sizeof(Push), "timer test spin"),
        draw_(context, [] {
          gpu::GraphicsPipelineDesc d;
          d.vertexSpirv = test_timer_spin_vert;
          d.fragmentSpirv = test_timer_spin_frag;
          d.colorFormats = {vk::Format::eR8G8B8A8Unorm};
          d.depthFormat = vk::Format::eUndefined;
          d.pushConstantBytes = sizeof(Push);
          d.name = "timer test draw";
          return d;
        }()) {
    std::vector<float> seeds(std::size_t(kSize) * kSize);
    for (std::size_t i = 0; i < seeds.size(); ++i) seeds[i] = float(i % 977) / 977.0f;
    values_.upload(std::span<const float>(seeds));
  }

  // One frame: draw, spin_a, spin_b in one submission, spin_c in a second (as the renderer's shade).
  FrameTimes run(gpu::GpuTimer& timer, const Iterations& iterations) {
    timer.reset();
    const auto start = std::chrono::steady_clock::now();
    context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      timer.begin(cmd, "draw");
      recordDraw(cmd, iterations.at("draw"));
      timer.end(cmd);
      timer.begin(cmd, "spin_a");
      recordSpin(cmd, iterations.at("spin_a"));
      timer.end(cmd);
      timer.begin(cmd, "spin_b");
      recordSpin(cmd, iterations.at("spin_b"));
      timer.end(cmd);
    });
    context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      timer.begin(cmd, "spin_c");
      recordSpin(cmd, iterations.at("spin_c"));
      timer.end(cmd);
    });
    FrameTimes times;
    times.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    for (const auto& [pass, ms] : timer.read()) times.passMs[pass] = ms;
    return times;
  }

  // Wall time of one submission holding only a spin pass (no timer): calibrates the slow passes.
  double spinWallMs(std::uint32_t iterations) {
    const auto start = std::chrono::steady_clock::now();
    context_.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { recordSpin(cmd, iterations); });
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }

 private:
  static constexpr gpu::Binding kBindings[] = {{0, vk::DescriptorType::eStorageBuffer}};

  void recordSpin(const vk::raii::CommandBuffer& cmd, std::uint32_t iterations) const {
    spin_.bind(cmd, gpu::Descriptors{}.buffer(0, values_));
    spin_.pushConstants(cmd, Push{iterations, kSize * kSize});
    cmd.dispatch(kSize * kSize / 64, 1, 1);
    gpu::computeToComputeAndHost(cmd);
  }

  void recordDraw(const vk::raii::CommandBuffer& cmd, std::uint32_t iterations) const {
    using Stage = vk::PipelineStageFlagBits2;
    using Access = vk::AccessFlagBits2;
    gpu::transition(cmd, target_, {vk::ImageLayout::eUndefined, vk::ImageLayout::eColorAttachmentOptimal, Stage::eAllCommands,
                                   Access::eMemoryRead, Stage::eColorAttachmentOutput, Access::eColorAttachmentWrite});
    const vk::Rect2D area{{0, 0}, {kSize, kSize}};
    const vk::RenderingAttachmentInfo attachment{.imageView = target_.view(),
                                                 .imageLayout = vk::ImageLayout::eColorAttachmentOptimal,
                                                 .loadOp = vk::AttachmentLoadOp::eClear,
                                                 .storeOp = vk::AttachmentStoreOp::eStore,
                                                 .clearValue = vk::ClearValue{.color = {std::array<float, 4>{0, 0, 0, 0}}}};
    cmd.beginRendering({.renderArea = area, .layerCount = 1, .colorAttachmentCount = 1, .pColorAttachments = &attachment});
    cmd.setViewport(0, vk::Viewport{0.0f, 0.0f, float(kSize), float(kSize), 0.0f, 1.0f});
    cmd.setScissor(0, area);
    draw_.bind(cmd, gpu::Descriptors{});
    draw_.pushConstants(cmd, Push{iterations, 0});
    cmd.draw(3, 1, 0, 0);
    cmd.endRendering();
    gpu::transition(cmd, target_, {vk::ImageLayout::eColorAttachmentOptimal, vk::ImageLayout::eShaderReadOnlyOptimal,
                                   Stage::eColorAttachmentOutput, Access::eColorAttachmentWrite, Stage::eComputeShader,
                                   Access::eShaderSampledRead});
  }

  gpu::Context& context_;
  gpu::Buffer values_;
  gpu::Image target_;
  gpu::ComputePipeline spin_;
  gpu::GraphicsPipeline draw_;
};

// Per pass and for the wall time: the median of `repeat` frames.
FrameTimes medianFrame(TimerFrame& frame, gpu::GpuTimer& timer, const Iterations& iterations, int repeat = 3) {
  std::vector<FrameTimes> runs;
  for (int i = 0; i < repeat; ++i) runs.push_back(frame.run(timer, iterations));
  auto median = [&](auto get) {
    std::vector<double> v;
    for (const FrameTimes& r : runs) v.push_back(get(r));
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  FrameTimes out;
  out.wallMs = median([](const FrameTimes& r) { return r.wallMs; });
  for (const std::string& pass : kPasses) out.passMs[pass] = median([&](const FrameTimes& r) { return r.passMs.at(pass); });
  return out;
}

std::string describe(const FrameTimes& t) {
  std::string s = "wall " + std::to_string(t.wallMs) + " ms;";
  for (const std::string& pass : kPasses) s += " " + pass + " " + std::to_string(t.passMs.at(pass));
  return s;
}

Iterations allCheap() {
  Iterations it;
  for (const std::string& pass : kPasses) it[pass] = kCheap;
  return it;
}

// Loop iterations that make a spin pass cost about `targetMs` of wall time on this machine.
std::uint32_t calibrateSlow(TimerFrame& frame, double targetMs) {
  frame.spinWallMs(kCheap);  // compiles the pipeline's variant before anything is timed
  const double base = frame.spinWallMs(kCheap);
  std::uint32_t iterations = 256;
  for (double ms = 0.0; iterations < (1u << 24); iterations *= 2) {
    ms = frame.spinWallMs(iterations) - base;
    if (ms >= targetMs / 2) return std::uint32_t(double(iterations) * std::clamp(targetMs / ms, 1.0, 2.0));
  }
  return iterations;
}

TEST(GpuTimer, SlowPassLandsInItsOwnRow) {
  gpu::Context& context = timerContext();
  TimerFrame frame(context);
  gpu::GpuTimer timer(context);
  std::cout << "device: " << context.deviceName() << " (" << context.driverInfo() << "), timer mode "
            << gpu::toString(timer.mode()) << "\n";
  // The fragment loop runs once per pixel like the compute loop; one calibration serves both.
  const std::uint32_t slow = calibrateSlow(frame, 120.0);
  medianFrame(frame, timer, allCheap(), 1);  // warm-up (pipeline variants, first-use allocations)
  const FrameTimes base = medianFrame(frame, timer, allCheap());
  std::cout << "all cheap: " << describe(base) << "\n";

  Iterations allSlow;
  for (const std::string& slowPass : kPasses) {
    Iterations iterations = allCheap();
    iterations[slowPass] = slow;
    allSlow[slowPass] = slow;
    const FrameTimes t = medianFrame(frame, timer, iterations);
    std::cout << slowPass << " slow: " << describe(t) << "\n";
    const double grew = t.wallMs - base.wallMs;
    ASSERT_GT(grew, 20.0) << "the slow " << slowPass << " pass did not slow the frame; calibration failed";
    const double own = t.passMs.at(slowPass) - base.passMs.at(slowPass);
    // Its own row takes (nearly) all of what the frame grew by ...
    EXPECT_GT(own, 0.7 * grew) << slowPass << "'s row missed its time: " << describe(t);
    EXPECT_LT(own, 1.3 * grew) << slowPass << "'s row has more than the frame grew by: " << describe(t);
    // ... and its neighbours stay cheap.
    for (const std::string& other : kPasses) {
      if (other == slowPass) continue;
      EXPECT_LT(t.passMs.at(other) - base.passMs.at(other), 0.15 * grew)
          << "the slow " << slowPass << " pass's time landed in " << other << ": " << describe(t);
    }
  }

  // With every pass slow the frame is GPU-bound: the rows add up to its wall time.
  const FrameTimes t = medianFrame(frame, timer, allSlow);
  std::cout << "all slow: " << describe(t) << "\n";
  double sum = 0.0;
  for (const auto& [pass, ms] : t.passMs) sum += ms;
  EXPECT_GT(sum, 0.85 * t.wallMs) << describe(t);
  EXPECT_LT(sum, 1.02 * t.wallMs) << describe(t);

  const auto messages = context.validationMessages();
  EXPECT_TRUE(messages.empty()) << messages.size() << " validation message(s), first: " << messages.front();
}

TEST(GpuTimer, ModeFollowsTheDeviceUnlessOverridden) {
  gpu::Context& context = timerContext();
  const bool cpu = context.physicalDevice().getProperties().deviceType == vk::PhysicalDeviceType::eCpu;
  const char* env = std::getenv("PENUMBRA_GPU_TIMER");
  if (env && *env) GTEST_SKIP() << "PENUMBRA_GPU_TIMER=" << env << " overrides the default";
  EXPECT_EQ(gpu::defaultTimerMode(context), cpu ? gpu::TimerMode::Fenced : gpu::TimerMode::Timestamps);
  EXPECT_EQ(gpu::GpuTimer(context, 4, gpu::TimerMode::Timestamps).mode(), gpu::TimerMode::Timestamps);
}

}  // namespace
}  // namespace penumbra::test
