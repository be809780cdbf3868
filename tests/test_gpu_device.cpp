// The Vulkan device comes up (lavapipe on a machine without a GPU) with validation on, and stays
// silent through full renders of every method, including a cube-map point light.
#include <gtest/gtest.h>

#include <memory>

#include "core/view.h"
#include "hybrid/method.h"
#include "render_fixture.h"

namespace penumbra::test {
namespace {

// Each pass's time (GPU timestamps, or CPU wall time for Embree) is positive, and together they
// fit in the frame's wall time: a timestamp period or a query read wrong breaks one or the other.
void expectPassesWithinTheFrame(const Frame& frame, const std::string& what) {
  double sum = 0.0;
  for (const auto& [pass, ms] : frame.stats.passMs) {
    EXPECT_GT(ms, 0.0) << what << ": " << pass;
    sum += ms;
  }
  EXPECT_FALSE(frame.stats.passMs.empty()) << what;
  EXPECT_LE(sum, frame.stats.totalMs * 1.001 + 0.01) << what << ": the passes take longer than the frame";
}

TEST(GpuDevice, ComesUpWithValidation) {
  gpu::Context& context = validatedContext();
  EXPECT_TRUE(context.validationEnabled());
  EXPECT_FALSE(context.deviceName().empty());
  EXPECT_FALSE(context.driverInfo().empty());
  EXPECT_GT(context.timestampPeriodNs(), 0.0f);
  std::cout << "device: " << context.deviceName() << " (" << context.driverInfo() << ")\n";
  expectValidationSilent();
}

TEST(GpuDevice, ValidationSilentThroughEveryMethod) {
  for (const std::string scene : {"builtin:courtyard:2", "builtin:room"}) {
    SceneRun run(scene, smallSettings(128, 512));
    for (const std::string& method : methodNames()) {
      Light light = run.light;
      if (method == "bitmask") {  // an area light over a planar receiver: the courtyard's ground (the room has none)
        if (scene == "builtin:room") continue;
        applyLightSize(light, 0.1f, run.scene.bounds());
      }
      const Frame frame = run.renderer->render(method, run.camera, light);
      EXPECT_EQ(frame.visibility.size(), 128u * 128u) << scene << " " << method;
      expectPassesWithinTheFrame(frame, scene + " " + method);
      expectValidationSilent();
    }
  }
}

TEST(GpuDevice, ValidationCatchesMisuse) {
  // The capture is live: a deliberately invalid call (a buffer of size 0) must be reported.
  gpu::Context& context = validatedContext();
  context.clearValidationMessages();
  try {
    vk::raii::Buffer bad(context.device(), vk::BufferCreateInfo{.size = 0, .usage = vk::BufferUsageFlagBits::eStorageBuffer});
  } catch (const std::exception&) {
  }
  EXPECT_FALSE(context.validationMessages().empty());
  context.clearValidationMessages();
}

// Context::shared: a key's object while any user holds it (pipelines made twice are made once),
// a new one after the last user let go, and another for another key.
TEST(GpuDevice, SharedObjectsLiveWhileUsed) {
  gpu::Context& context = validatedContext();
  int made = 0;
  const auto make = [&] { return std::shared_ptr<const void>(std::make_shared<int>(++made)); };
  std::shared_ptr<const void> a = context.shared("test a", make), again = context.shared("test a", make);
  EXPECT_EQ(a, again);
  const std::shared_ptr<const void> b = context.shared("test b", make);
  EXPECT_NE(a, b);
  EXPECT_EQ(made, 2);
  a.reset();
  EXPECT_EQ(context.shared("test a", make), again) << "still held by `again`";
  again.reset();
  const auto fresh = std::static_pointer_cast<const int>(context.shared("test a", make));
  EXPECT_EQ(made, 3);
  EXPECT_EQ(*fresh, 3);
}

TEST(GpuDevice, PerPassTimesAreReported) {
  SceneRun run("builtin:square", smallSettings(64, 256));
  const Frame frame = run.render("sm");
  std::vector<std::string> passes;
  for (const auto& [pass, ms] : frame.stats.passMs) passes.push_back(pass);
  expectPassesWithinTheFrame(frame, "sm");
  EXPECT_EQ(passes, (std::vector<std::string>{"gbuffer", "shadow_map", "lookup", "shade"}));
  // Fitted to the view, the camera pass runs first and the fit gets its own row.
  RenderSettings fitted = smallSettings(64, 256);
  fitted.fitLightToView = true;
  SceneRun fittedRun("builtin:square", fitted);
  passes.clear();
  for (const auto& [pass, ms] : fittedRun.render("sm").stats.passMs) passes.push_back(pass);
  EXPECT_EQ(passes, (std::vector<std::string>{"gbuffer", "light_fit", "shadow_map", "lookup", "shade"}));
  expectValidationSilent();
}

}  // namespace
}  // namespace penumbra::test
