// Method ref: the ground truth. The camera pass gives the shading points (the same ones every
// method shades, so differences are shadow error only); Embree traces every light sample of every
// covered pixel on all CPU cores.
#include <chrono>

#include "hybrid/frame_context.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"

namespace penumbra {
namespace {

class ReferenceMethod final : public Method {
 public:
  std::uint32_t samplesPerPixel(const RenderSettings& settings) const override {
    return settings.referenceSpp > 0 ? settings.referenceSpp : settings.spp;
  }

  void run(FrameContext& r, FrameStats& stats) override {
    const EmbreeTracer& tracer = r.embree(stats);
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      r.gbuffer().recordReadback(cmd);
    });
    const auto start = std::chrono::steady_clock::now();
    const std::vector<glm::vec4> positions = r.gbuffer().positions();
    const std::vector<glm::vec4> normals = r.gbuffer().normals();
    const std::uint32_t spp = r.frameData().spp;
    std::vector<shared::ShadingPoint> points;
    for (std::uint32_t i = 0; i < positions.size(); ++i) {
      if (positions[i].w != 0.0f) points.push_back({glm::vec3(positions[i]), i, glm::vec3(normals[i]), spp});
    }
    std::vector<float> traced(points.size());
    stats.raysTraced = tracer.traceShadows(points, r.frameData().light, traced);
    std::vector<float> visibility(positions.size(), 1.0f);
    for (std::size_t k = 0; k < points.size(); ++k) visibility[points[k].pixel] = traced[k];
    r.visibility().upload(std::span<const float>(visibility));
    stats.tracer = "embree";
    stats.pipFraction = 1.0;  // every covered pixel is traced
    stats.addPass("trace", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
};

}  // namespace

void register_reference_method(Registry& r) {
  r.method("ref", [] { return std::make_unique<ReferenceMethod>(); });
}

}  // namespace penumbra
