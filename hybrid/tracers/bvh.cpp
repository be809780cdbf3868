// Tracer bvh: the GPU BVH traversed in compute shaders (raytrace/bvh_tracer.h).
#include "hybrid/registry.h"
#include "hybrid/frame_context.h"

namespace penumbra {
namespace {

std::unique_ptr<ShadowTracer> make(const gpu::Context& context, const Scene& scene, const RenderSettings&) {
  return std::make_unique<BvhTracer>(context, scene);
}

void report(const ShadowTracer& tracer, const RenderSettings&, FrameStats& stats) {
  const BvhStats& bvh = static_cast<const BvhTracer&>(tracer).stats();
  stats.setupMs["bvh_build"] = bvh.buildMs;
  stats.memoryBytes["bvh"] = bvh.bytes;
}

}  // namespace

void register_bvh(Registry& r) { r.tracer("bvh", {"GPU compute BVH", make, report}); }

}  // namespace penumbra
