#include "hybrid/render_settings.h"

namespace penumbra {

const Options<RenderSettings>& renderOptions() {
  static const Options<RenderSettings> options = [] {
    using S = RenderSettings;
    Options<S> o;
    o.add(&S::shadowMap, raster::shadowMapOptions());
    o.group("Shadow maps");
    o.choice("--light-fit", "light_fit", &S::fitLightToView,
             "Directional and spot lights (point-like): fit the shadow map to what the camera sees (view) or to the "
             "whole scene (scene)",
             {{"view", true}, {"scene", false}});
    o.choice("--reuse-light-passes", "reuse_light_passes", &S::reuseLightPasses,
             "Keep the shadow map and edge pyramid while the light and the geometry stay still, as an engine keeps a "
             "still light's map (on), or render them every frame (off)",
             {{"on", true}, {"off", false}});
    o.number(
        "--light-maps-memory", "light_maps_memory", &S::lightMapsMiB,
        "With --reuse-light-passes on and several lights: MiB the lights' own maps may keep (each light's map, "
        "thin mask and edge pyramid, refreshed only when the light or the geometry its map sees moved); the lights "
        "past it share maps rendered again for each",
        0u, 1u << 20);
    o.choice("--light-map-res", "light_map_res", &S::footprintMaps,
             "Point and spot lights with a range: a map as fine as the range's nearest approach to the camera needs "
             "(footprint: a texel at most half a pixel there, 128 to --shadow-map-res texels), or --shadow-map-res "
             "for every light (fixed)",
             {{"footprint", true}, {"fixed", false}});
    o.add(&S::pip, raster::pipOptions());
    o.add(&S::thin, raster::thinOptions());
    o.group("Ray tracing");
    o.number("--ray-epsilon", "ray_epsilon", &S::rayEpsilon, "Shadow ray origin offset, fraction of the scene radius",
             0.0f);
    o.choice("--lights-trace", "lights_trace", &S::oneLightsTrace,
             "A frame of several lights on a GPU tracer: frt (and srt where it traces every covered pixel) traces its "
             "lights in one dispatch per batch of lights (one), or each light in a dispatch of its own (each)",
             {{"one", true}, {"each", false}});
    o.number("--light-error", "light_error", &S::lightError,
             "srt and frt on a GPU tracer: where a light's shadow can change a pixel's shaded value by less than this "
             "(linear, 0..1 per channel: the light's unshadowed direct term there), srt keeps the map's answer and frt "
             "takes the light unshadowed, tracing no ray; the image errs there by less than it per light (0: exact)",
             0.0f, 1.0f);
    o.flag("--simulate-bandwidth", "simulate_bandwidth", &S::simulateBandwidth,
           "srt/frt on the bvh tracer: replay the trace on the CPU and report its simulated memory traffic");
    o.group("Selective ray tracing (srt)");
    o.choice("--srt-choice", "srt_choice", &S::srtChoice,
             "srt per frame: auto takes the cheaper of its two paths by its own measurements of both (classify and "
             "trace the doubtful pixels, or trace every covered pixel; the first frame runs both, every 32nd the other "
             "again), off always classifies",
             {{"auto", true}, {"off", false}});
    o.group("Soft shadows and denoising");
    o.number("--spp", "spp", &S::spp, "Light samples per pixel for area lights", 1u, 4096u)
        .sweep("spp", {"srt", "frt", "ls", "bitmask"}, true);
    o.add(&S::denoise, denoiseOptions());
    o.flag("--shared-samples", "shared_samples", &S::sharedSamples,
           "Every pixel uses the same light samples, the pattern method bitmask looks up, so that ref, frt and srt see "
           "bitmask's samples (default: a pattern per pixel)");
    o.group("Baselines: pcf, msm, bitmask");
    o.choice("--pcf-kernel", "pcf_kernel", &S::pcfFilter, "PCF kernel of method pcf",
             {{"3x3", std::uint32_t(FILTER_PCF3)},
              {"5x5", std::uint32_t(FILTER_PCF5)},
              {"poisson", std::uint32_t(FILTER_POISSON)}})
        .sweep("", {"pcf"});
    o.number("--msm-maps", "msm_maps", &S::msmMaps, "Shadow maps (light samples) averaged by method msm", 1u, 256u)
        .sweep("K", {"msm"});
    o.add(&S::bitmask, raster::bitmaskOptions());
    o.add(&S::indirect, indirectOptions());
    o.add(&S::lineSpace, lineSpaceOptions());
    return o;
  }();
  return options;
}

}  // namespace penumbra
