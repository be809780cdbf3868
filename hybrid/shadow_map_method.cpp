// Methods sm, pcf and pcss: camera pass, light pass, and a shadow-map lookup from the light's
// centre (unfiltered for sm, the configured PCF kernel for pcf, blocker search + penumbra-sized PCF
// for pcss). sm and pcf treat area lights as their centre; pcss uses the light's size.
#include "hybrid/frame_context.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"

namespace penumbra {
namespace {

enum class ShadowMapFilter { None, Pcf, Pcss };

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

  void run(FrameContext& r, FrameStats& stats) override {
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      r.recordShadowMap(cmd, stats);
      r.timer().begin(cmd, "lookup");
      r.shadowLookup().record(cmd, r.gbuffer(), r.shadowMap(), r.frameBuffer(), r.visibility(), r.lightRect());
      r.timer().end(cmd);
      r.recordShade(cmd);
    });
  }

 private:
  ShadowMapFilter filter_;
};

}  // namespace

void register_shadow_map_method(Registry& r) {
  r.method("sm", [] { return std::make_unique<ShadowMapMethod>(ShadowMapFilter::None); });
  r.method("pcf", [] { return std::make_unique<ShadowMapMethod>(ShadowMapFilter::Pcf); });
  r.method("pcss", [] { return std::make_unique<ShadowMapMethod>(ShadowMapFilter::Pcss); });
}

}  // namespace penumbra
