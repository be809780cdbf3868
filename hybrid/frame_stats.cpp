#include "hybrid/frame_stats.h"

#include <cmath>

namespace penumbra {

namespace {
// PSNR is +infinity for identical buffers, which JSON cannot hold: null says "no difference".
nlohmann::json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

nlohmann::json toJson(const ErrorMetrics& e) {
  return {{"rmse", e.rmse}, {"mae", e.mae}, {"max", e.max}, {"wrong_pixel_fraction", e.wrongPixelFraction},
          {"psnr", finiteOrNull(e.psnr)}, {"pixels", e.pixels}};
}

nlohmann::json toJson(const ImageErrorMetrics& e) {
  return {{"rmse", e.rmse}, {"mae", e.mae}, {"max", e.max}, {"psnr", finiteOrNull(e.psnr)}, {"flip_mean", e.flipMean},
          {"pixels", e.pixels}};
}

void to_json(nlohmann::json& j, const MaskRule& r) {
  const auto pixels = [](const MaskPixels& p) {
    return nlohmann::json{{"pixels", p.pixels}, {"penumbra", p.penumbra}, {"lit", p.lit}, {"dark", p.dark}};
  };
  j = {{"holds", pixels(r.holds)}, {"alone", pixels(r.alone)}};
}

void FrameStats::addPass(const std::string& pass, double ms) {
  for (auto& [name, total] : passMs) {
    if (name == pass) {
      total += ms;
      return;
    }
  }
  passMs.emplace_back(pass, ms);
}

nlohmann::json FrameStats::toJson() const {
  auto orNull = [](const auto& optional) { return optional ? nlohmann::json(*optional) : nlohmann::json(nullptr); };
  nlohmann::json times = {{"total", totalMs}};
  if (totalSpreadMs) {
    times["total_min"] = totalSpreadMs->minMs;
    times["total_max"] = totalSpreadMs->maxMs;
    times["runs"] = totalSpreadMs->runs;
  }
  for (const auto& [pass, ms] : passMs) times[pass] = ms;
  nlohmann::json json = {
      {"method", method},
      {"tracer", orNull(tracer)},
      {"term", term.value_or("shadow")},
      {"denoise", orNull(denoise)},
      {"srt_path", orNull(srtPath)},
      {"time_ms", times},
      {"reused_passes", reusedPasses},
      {"pip_fraction", orNull(pipFraction)},
      {"rays_traced", orNull(raysTraced)},
      {"pip_pixels", orNull(pipPixels)},
      {"pip_miss_fraction", orNull(pipMissFraction)},
      {"penumbra_miss_fraction", orNull(penumbraMissFraction)},
      {"light_error_max", orNull(lightErrorMax)},
      {"miss_causes", orNull(missCauses)},
      {"mask_rules", orNull(maskRules)},
      {"notes", notes},
      {"traversal", nodeVisits
                        ? nlohmann::json{{"node_visits", *nodeVisits},
                                         {"triangle_tests", orNull(triangleTests)},
                                         {"node_visits_per_ray",
                                          raysTraced && *raysTraced ? double(*nodeVisits) / double(*raysTraced) : 0.0}}
                        : nlohmann::json(nullptr)},
      {"samples_per_pixel", samplesPerPixel},
      {"memory_bytes", memoryBytes},
      {"counts", counts},
      {"setup_ms", setupMs},
      {"refit", refit ? nlohmann::json{{"ms", refit->ms},
                                       {"sah", refit->sah},
                                       {"built_sah", refit->builtSah},
                                       {"sah_growth", refit->growth},
                                       {"rebuilt", refit->rebuilt},
                                       {"rebuilds", refit->rebuilds}}
                      : nlohmann::json(nullptr)},
      {"light_map_zoom", orNull(lightMapZoom)},
      {"thin_pass", thinPass ? nlohmann::json{{"faces", thinPass->faces},
                                              {"triangles", thinPass->triangles},
                                              {"thin_triangles", thinPass->thin},
                                              {"selection_reused", thinPass->reused}}
                             : nlohmann::json(nullptr)},
      {"error", error ? penumbra::toJson(*error) : nlohmann::json(nullptr)},
      {"image_error", imageError ? penumbra::toJson(*imageError) : nlohmann::json(nullptr)},
      {"trace_bytes_simulated", orNull(traceBytesSimulated)},
      {"trace_bytes_per_ray", traceBytesSimulated && raysTraced && *raysTraced
                                  ? nlohmann::json(double(*traceBytesSimulated) / double(*raysTraced))
                                  : nlohmann::json(nullptr)},
      {"trace_lines_simulated", orNull(traceLinesSimulated)},
      {"raster_bytes_estimated", orNull(rasterBytesEstimated)},
      {"bandwidth", bandwidth}};
  for (const FrameStats& light : lights) json["lights"].push_back(light.toJson());
  return json;
}

}  // namespace penumbra
