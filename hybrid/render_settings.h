// What a Renderer renders with: resolution, samples, and each pass's, method's and tracer's settings.
#pragma once
#include <cstdint>
#include <string>

#include "core/options.h"
#include "hybrid/denoise_pass.h"
#include "hybrid/indirect_pass.h"
#include "raster/bitmask_pass.h"
#include "raster/pip_classify_pass.h"
#include "raster/shadow_map_pass.h"
#include "raster/thin_triangle_pass.h"
#include "raytrace/linespace_tracer.h"
#include "shared/light.h"

namespace penumbra {

struct RenderSettings {
  std::uint32_t width = 256;
  std::uint32_t height = 256;
  std::uint32_t spp = 16;            // light samples per pixel for area lights
  std::uint32_t referenceSpp = 0;    // samples for `ref`; 0 = spp
  raster::ShadowMapSettings shadowMap;
  std::uint32_t pcfFilter = FILTER_PCF3;  // kernel of `pcf`: FILTER_PCF3, FILTER_PCF5, FILTER_POISSON
  std::uint32_t msmMaps = 4;         // `msm`: shadow maps from this many light samples, averaged
  float rayEpsilon = 1e-4f;          // shadow-ray origin offset, fraction of the scene radius
  // Ray tracer of srt and frt: "bvh" (GPU compute), "rq" (GPU ray queries), "embree" (CPU), "ls"
  // (line space), or "auto" (resolveTracer, hybrid/registry.h).
  std::string tracer = "auto";
  LineSpaceSettings lineSpace;       // tracer "ls" and method ls: N, depth, memory budget
  raster::PipSettings pip;
  raster::ThinTriangleSettings thin;
  // Directional and spot lights with point-like extent: fit the centre map to the receivers the
  // camera sees (raster/light_fit_pass.h) instead of the whole scene (false, the default: the
  // finer texels halve PIP but let srt miss more along grazing edges, bench/results/passes.md).
  bool fitLightToView = false;
  bool simulateBandwidth = false;    // srt/frt on the bvh tracer: replay the trace for its memory traffic (raytrace/bandwidth_model.h)
  // --lights-trace: a frame of several lights on a GPU tracer traces every covered pixel of the
  // lights that take that path in one dispatch per batch of lights (FrameContext::traceWithLights),
  // not one per light.
  bool oneLightsTrace = true;
  // --light-error: where a light's shadow changes a pixel's shaded value by less than this (linear
  // units, shared::shadowWeight), srt keeps the map's answer and an in-place trace takes the light
  // unshadowed, without rays; the image errs there by less than it per light. 0: every pixel exact.
  float lightError = 0.0f;
  // A frame whose light map would be the last one's (same map placement, geometry unmoved) keeps
  // the last shadow map and edge pyramid instead of rendering them again, as an engine keeps a
  // still light's map (--reuse-light-passes; the demo's default). Off: every frame renders them.
  bool reuseLightPasses = false;
  // --light-maps-memory: with reuseLightPasses and several lights, each light keeps its own map, thin
  // mask and edge pyramid (each refreshed only when the light or the geometry its map sees moved)
  // while their estimated sum stays within this many MiB; the lights past it share maps rendered
  // again for each of them (FrameContext::chooseMaps).
  std::uint32_t lightMapsMiB = 4096;
  // --light-map-res: point and spot lights with a range get the map resolution their range's
  // footprint on screen needs (FrameContext::mapResolution), at most shadowMap.resolution.
  bool footprintMaps = true;
  // srt takes, per frame, whichever of its paths (classify, or trace every covered pixel) its own
  // measurements say is cheaper (--srt-choice auto; hybrid/traced_method.cpp). Off: always classify.
  bool srtChoice = false;
  DenoiseSettings denoise;           // srt/frt with an area light: the shadow denoiser (hybrid/denoise_pass.h)
  // Every pixel uses the same light samples, the pattern method bitmask looks up (--shared-samples):
  // the reference and the tracers then see bitmask's samples.
  bool sharedSamples = false;
  raster::BitmaskSettings bitmask;   // method bitmask: map resolution, receiver
  IndirectSettings indirect;         // methods ao and indirect: rays per pixel, ao radius, tracer
};

// The options of the settings declared where they are used (the passes' own and RenderSettings'),
// as the command line takes them (apps/declared_options.h).
const Options<RenderSettings>& renderOptions();

}  // namespace penumbra
