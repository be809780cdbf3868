// Methods sm, pcf and pcss: camera pass, light pass, and a shadow-map lookup from the light's
// centre (unfiltered for sm, the configured PCF kernel for pcf, blocker search + penumbra-sized PCF
// for pcss). sm and pcf treat area lights as their centre; pcss uses the light's size.
#include "hybrid/method.h"
#include "hybrid/renderer.h"

namespace penumbra {
namespace {

class ShadowMapMethod final : public Method {
 public:
  explicit ShadowMapMethod(ShadowMapFilter filter) : filter_(filter) {}

  std::uint32_t shadowFilter(const RenderSettings& settings) const override {
    switch (filter_) {
      case ShadowMapFilter::Pcf: return settings.pcfFilter;
      case ShadowMapFilter::Pcss: return FILTER_PCSS;
      case ShadowMapFilter::None: break;
    }
    return FILTER_NONE;
  }
  std::uint32_t samplesPerPixel(const RenderSettings&) const override { return 1; }
  bool readsShadowMap() const override { return true; }

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
  ShadowMapFilter filter_;
};

}  // namespace

std::unique_ptr<Method> makeShadowMapMethod(ShadowMapFilter filter) { return std::make_unique<ShadowMapMethod>(filter); }

}  // namespace penumbra
