// Shared by the render tests: one validated Vulkan context for the whole test binary, and a helper
// that renders a scene's default view with a method. Validation messages fail the test that
// caused them.
#pragma once
#include <algorithm>
#include <functional>
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

// Whether one of the frame's notes says `text`.
inline bool hasNote(const Frame& frame, const std::string& text) {
  const auto& notes = frame.stats.notes;
  return std::any_of(notes.begin(), notes.end(),
                     [&](const std::string& n) { return n.find(text) != std::string::npos; });
}

struct SceneRun {
  Scene scene;
  Camera camera;
  Light light;
  std::unique_ptr<Renderer> renderer;

  SceneRun(const std::string& spec, const RenderSettings& settings) : SceneRun(loadScene(spec), settings) {}
  SceneRun(Scene built, const RenderSettings& settings) : scene(std::move(built)) {
    camera = *scene.camera;
    light = scene.lights.front();
    renderer = std::make_unique<Renderer>(validatedContext(), scene, settings);
  }
  Frame render(const std::string& method) { return renderer->render(method, camera, light); }
};

// Fraction of covered pixels where two visibility buffers differ by more than 0.5; with
// `awayFromEdges`, only pixels whose 3x3 neighbourhood in `a` is all covered and all lit or all dark.
inline double differingPixels(const Frame& a, const Frame& b, bool awayFromEdges = false) {
  const int w = int(a.width), h = int(a.height);
  auto uniform = [&](int x, int y) {
    if (x < 1 || y < 1 || x >= w - 1 || y >= h - 1) return false;
    const bool dark = a.visibility[std::size_t(y * w + x)] < 0.5f;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const std::size_t j = std::size_t((y + dy) * w + x + dx);
        if (!a.covered[j] || (a.visibility[j] < 0.5f) != dark) return false;
      }
    }
    return true;
  };
  std::size_t covered = 0, differ = 0;
  for (std::size_t i = 0; i < a.visibility.size(); ++i) {
    if (!a.covered[i]) continue;
    ++covered;
    if (awayFromEdges && !uniform(int(i % std::size_t(w)), int(i / std::size_t(w)))) continue;
    differ += std::abs(a.visibility[i] - b.visibility[i]) > 0.5f;
  }
  return covered ? double(differ) / double(covered) : 1.0;
}

// The message of the InputError that f throws, or "(no InputError)".
inline std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

inline RenderSettings smallSettings(std::uint32_t size = 256, std::uint32_t shadowMapRes = 2048) {
  RenderSettings s;
  s.width = size;
  s.height = size;
  s.shadowMap.resolution = shadowMapRes;
  return s;
}

}  // namespace penumbra::test
