// Tracer ls: the N-tree line space (raytrace/linespace_tracer.h), built with RenderSettings::lineSpace.
#include <cstdio>

#include "hybrid/registry.h"
#include "hybrid/frame_context.h"

namespace penumbra {
namespace {

std::unique_ptr<ShadowTracer> make(const gpu::Context& context, const Scene& scene, const RenderSettings& settings) {
  return std::make_unique<LineSpaceTracer>(context, scene, settings.lineSpace);
}

void report(const ShadowTracer& tracer, const RenderSettings& settings, FrameStats& stats) {
  const auto& lineSpace = static_cast<const LineSpaceTracer&>(tracer);
  const LineSpaceStats& ls = lineSpace.stats();
  stats.setupMs["linespace_build"] = ls.buildMs;
  stats.memoryBytes["linespace"] = ls.bytes;
  char note[200];
  std::snprintf(note, sizeof(note),
                "line space (N=%u, d=%u, %s shadows): %llu subdivided nodes, %.1f MB, build %.0f ms (tree %.0f, bits "
                "%.0f), %.1f%% bits set",
                ls.n, ls.depth, shadowsName(settings.lineSpace.shadows), (unsigned long long)ls.nodes,
                double(ls.bytes) / 1e6, ls.buildMs, ls.treeMs, ls.lineSpaceMs, 100.0 * ls.filledFraction);
  stats.notes.push_back(note);
  if (ls.exactBytes() > 0) {
    std::snprintf(note, sizeof(note),
                  "line space exact shadows: %llu leaf cells, %llu triangle references, %.1f MB of it (leaf groups "
                  "%.1f, leaves %.1f, lists %.1f, triangles %.1f)",
                  (unsigned long long)ls.leaves, (unsigned long long)ls.leafTriangleRefs, double(ls.exactBytes()) / 1e6,
                  double(ls.leafGroupBytes) / 1e6, double(ls.leafBytes) / 1e6, double(ls.leafTriangleBytes) / 1e6,
                  double(ls.triangleBytes) / 1e6);
    stats.notes.push_back(note);
  }
  if (const SceneAccelerationStructures* moving = lineSpace.movingStructures()) {
    stats.memoryBytes["acceleration_structures"] = moving->stats().bytes;
    stats.notes.push_back("line space: moving meshes traced with ray queries");
  }
}

}  // namespace

void register_ls(Registry& r) { r.tracer("ls", {"line space, GPU", make, report}); }

}  // namespace penumbra
