// Tracer embree: the CPU reference (raytrace/embree_tracer.h), which method ref traces on too.
#include "hybrid/registry.h"
#include "hybrid/frame_context.h"

namespace penumbra {
namespace {

std::unique_ptr<ShadowTracer> make(const gpu::Context&, const Scene& scene, const RenderSettings&) {
  return std::make_unique<EmbreeTracer>(scene);
}

void report(const ShadowTracer& tracer, const RenderSettings&, FrameStats& stats) {
  stats.setupMs["embree_build"] = static_cast<const EmbreeTracer&>(tracer).buildMs();  // with every frame using it
}

}  // namespace

void register_embree(Registry& r) { r.tracer("embree", {"CPU, the reference", make, report}); }

}  // namespace penumbra
