#include "hybrid/renderer.h"

#include <chrono>

#include "core/units.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"

namespace penumbra {

Renderer::Renderer(const gpu::Context& context, const Scene& scene, const RenderSettings& settings)
    : frameContext_(std::make_unique<FrameContext>(context, scene, settings)) {}

Renderer::~Renderer() = default;

Frame Renderer::render(const std::string& methodName, const Camera& camera, const Light& light) {
  std::unique_ptr<Method>& method = methods_[methodName];
  if (!method) method = makeMethod(methodName);
  FrameStats stats;
  stats.method = methodName;
  frameContext_->begin(camera, light, *method, frame_, stats);
  const auto start = std::chrono::steady_clock::now();
  if (method->readsShadowMap()) frameContext_->fitLightToView(stats);
  method->run(*frameContext_, stats);
  frameContext_->shade(*method, stats);
  stats.totalMs = msSince(start);
  return frameContext_->readBack(*method, std::move(stats));
}

}  // namespace penumbra
