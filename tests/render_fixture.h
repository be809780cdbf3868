// Shared by the render tests: one validated Vulkan context for the whole test binary, and a helper
// that renders a scene's default view with a method. Validation messages fail the test that
// caused them.
#pragma once
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "core/scene_loader.h"
#include "gpu/context.h"
#include "hybrid/renderer.h"

namespace penumbra::test {

inline gpu::Context& validatedContext() {
  static gpu::Context context({.validate = true, .printMessages = true});
  return context;
}

// Fails the current test if the Vulkan validation layer said anything since the last check.
inline void expectValidationSilent() {
  gpu::Context& context = validatedContext();
  const auto messages = context.validationMessages();
  EXPECT_TRUE(messages.empty()) << messages.size() << " validation message(s), first: " << messages.front();
  context.clearValidationMessages();
}

struct SceneRun {
  Scene scene;
  Camera camera;
  Light light;
  std::unique_ptr<Renderer> renderer;

  SceneRun(const std::string& spec, const RenderSettings& settings) : scene(loadScene(spec)) {
    camera = *scene.camera;
    light = scene.lights.front();
    renderer = std::make_unique<Renderer>(validatedContext(), scene, settings);
  }
  Frame render(const std::string& method) { return renderer->render(method, camera, light); }
};

inline RenderSettings smallSettings(std::uint32_t size = 256, std::uint32_t shadowMapRes = 2048) {
  RenderSettings s;
  s.width = size;
  s.height = size;
  s.shadowMap.resolution = shadowMapRes;
  return s;
}

}  // namespace penumbra::test
