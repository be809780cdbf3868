// Methods sm and pcf: camera pass, light pass, and a shadow-map lookup from the light's centre
// (unfiltered for sm, the configured PCF kernel for pcf). Area lights are treated as their centre.
#include "hybrid/method.h"
#include "hybrid/renderer.h"

namespace penumbra {
namespace {

class ShadowMapMethod final : public Method {
 public:
  explicit ShadowMapMethod(bool filtered) : filtered_(filtered) {}

  std::uint32_t shadowFilter(const RenderSettings& settings) const override {
    return filtered_ ? settings.pcfFilter : FILTER_NONE;
  }
  std::uint32_t samplesPerPixel(const RenderSettings&) const override { return 1; }

  void run(Renderer& r, FrameStats& stats) override {
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      r.recordShadowMap(cmd, stats);
      r.timer().begin(cmd, "lookup");
      r.shadowLookup().record(cmd, r.gbuffer(), r.shadowMap(), r.frameBuffer(), r.visibility());
      r.timer().end(cmd);
    });
  }

 private:
  bool filtered_;
};

}  // namespace

std::unique_ptr<Method> makeShadowMapMethod(bool filtered) { return std::make_unique<ShadowMapMethod>(filtered); }

}  // namespace penumbra
