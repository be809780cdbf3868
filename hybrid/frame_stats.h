// What one method reports for one frame (the stats contract later methods extend).
// Fields that do not apply to a method stay empty and are written as null, never invented.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/metrics.h"
#include "core/miss_explainer.h"

namespace penumbra {

struct FrameStats {
  std::string method;
  std::optional<std::string> tracer;    // which ray tracer answered rays, if any
  std::optional<std::string> term;      // methods ao and indirect: what the frame's visibility holds
  std::optional<std::string> denoise;   // the denoiser's mode (spatial, temporal), where it ran
  std::optional<std::string> srtPath;   // srt with --srt-choice auto: "classify" or "trace_all" this frame
  std::optional<double> pipFraction;    // fraction of covered pixels classified for tracing
  std::optional<std::uint64_t> raysTraced;
  std::optional<std::uint64_t> pipPixels;       // pixels handed to the tracer
  std::optional<double> pipMissFraction;        // of the pixels sm gets wrong, those not traced (when compared)
  std::optional<double> penumbraMissFraction;   // of the reference's penumbra pixels (0 < v < 1), those not traced
  // --light-error, when compared: the most the method's visibility errors changed a pixel's shaded
  // value (linear: shared::shadowWeight times |visibility - reference|, summed over the frame's lights)
  std::optional<double> lightErrorMax;
  std::optional<std::map<std::string, std::uint64_t>> missCauses;  // --explain-misses: missed pixels by cause
  std::optional<std::map<std::string, MaskRule>> maskRules;        // --explain-misses, area lights: the mask's rules
  std::vector<std::string> notes;               // what a reader of the numbers should know
  std::optional<std::uint64_t> nodeVisits;      // traversal steps, where the tracer counts them
  std::optional<std::uint64_t> triangleTests;
  std::uint32_t samplesPerPixel = 1;    // light samples per traced pixel (1 for point-like lights)
  double totalMs = 0.0;                 // wall time of the frame, setup excluded
  struct Spread {
    double minMs = 0.0, maxMs = 0.0;
    std::uint32_t runs = 1;
  };
  std::optional<Spread> totalSpreadMs;  // over repeated frames, when repeated
  std::vector<std::pair<std::string, double>> passMs;  // per pass: GPU timestamps, CPU wall time
  std::vector<std::string> reusedPasses;  // passes not run: their last output still held (RenderSettings::reuseLightPasses)
  std::map<std::string, std::uint64_t> memoryBytes;    // per structure
  std::map<std::string, std::uint64_t> counts;         // what a pass counted (bitmask: influence regions, fill)
  std::map<std::string, double> setupMs;               // one-time work (e.g. acceleration build)
  // Dynamic scenes: the tracer's dynamic BVH after the last Renderer::sceneMoved() (refit, or a
  // rebuild when refitting grew its SAH cost past the threshold).
  struct Refit {
    double ms = 0.0;          // refit (or rebuild) and write to the GPU buffers, wall clock
    double sah = 0.0;         // SAH cost of the dynamic BVH now
    double builtSah = 0.0;    // ... when it was last built
    double growth = 1.0;      // the refit tree's SAH over the built one's, which decided (> limit: rebuilt)
    bool rebuilt = false;     // this update rebuilt it
    std::uint64_t rebuilds = 0;  // rebuilds so far
  };
  std::optional<Refit> refit;
  // srt's thin pass: light faces, the scene's triangles, the thin ones drawn (summed over faces),
  // and whether the selection of the previous frame was reused (light and geometry unchanged).
  struct ThinPass {
    std::uint32_t faces = 1;
    std::uint64_t triangles = 0, thin = 0;
    bool reused = false;
  };
  std::optional<ThinPass> thinPass;
  // The centre map's texels per whole-scene-map texel (along each axis) after fitting it to the
  // view (Renderer fitLightToView; 1 = not narrowed).
  std::optional<double> lightMapZoom;
  std::optional<ErrorMetrics> error;                   // vs the reference, when compared
  std::optional<ImageErrorMetrics> imageError;         // shaded image vs the reference's, when compared
  // --simulate-bandwidth (raytrace/bandwidth_model.h): DRAM bytes and 128-byte lines of the trace
  // kernel as simulated, its breakdown per stream, and the estimate for the raster passes.
  std::optional<std::uint64_t> traceBytesSimulated, traceLinesSimulated, rasterBytesEstimated;
  nlohmann::json bandwidth;  // null unless simulated
  // A frame of several lights: each light's own (the frame's are their sums; its error counts the
  // pixels of every light).
  std::vector<FrameStats> lights;

  void addPass(const std::string& pass, double ms);  // adds to an existing pass of that name
  nlohmann::json toJson() const;
};

nlohmann::json toJson(const ErrorMetrics& error);
// metrics.json's mask_rules entries (for nlohmann::json)
void to_json(nlohmann::json& j, const MaskRule& rule);
nlohmann::json toJson(const ImageErrorMetrics& error);

}  // namespace penumbra
