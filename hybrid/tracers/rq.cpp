// Tracer rq: inline ray queries on the driver's acceleration structures (raytrace/ray_query_tracer.h).
#include <cstdio>

#include "hybrid/registry.h"
#include "hybrid/frame_context.h"

namespace penumbra {
namespace {

std::unique_ptr<ShadowTracer> make(const gpu::Context& context, const Scene& scene, const RenderSettings&) {
  return std::make_unique<RayQueryTracer>(context, scene);
}

void report(const ShadowTracer& tracer, const RenderSettings&, FrameStats& stats) {
  const AccelerationStats& as = static_cast<const RayQueryTracer&>(tracer).stats();
  stats.setupMs["rq_build"] = as.buildMs;
  stats.memoryBytes["acceleration_structures"] = as.bytes;
  char note[200];
  std::snprintf(note, sizeof(note),
                "ray queries: %u bottom-level structures, %.1f MB (static ones compacted from %.1f MB), build %.0f ms",
                as.bottomLevels, double(as.bytes) / 1e6, double(as.uncompactedBytes) / 1e6, as.buildMs);
  stats.notes.push_back(note);
}

}  // namespace

void register_rq(Registry& r) { r.tracer("rq", {"GPU ray queries on driver-built acceleration structures", make, report}); }

}  // namespace penumbra
