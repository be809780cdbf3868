#include "hybrid/frame_stats.h"

namespace penumbra {

nlohmann::json toJson(const ErrorMetrics& e) {
  return {{"rmse", e.rmse}, {"mae", e.mae}, {"max", e.max}, {"wrong_pixel_fraction", e.wrongPixelFraction}, {"pixels", e.pixels}};
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
  return {{"method", method},
          {"tracer", orNull(tracer)},
          {"time_ms", times},
          {"pip_fraction", orNull(pipFraction)},
          {"rays_traced", orNull(raysTraced)},
          {"pip_pixels", orNull(pipPixels)},
          {"pip_miss_fraction", orNull(pipMissFraction)},
          {"penumbra_miss_fraction", orNull(penumbraMissFraction)},
          {"notes", notes},
          {"traversal", nodeVisits ? nlohmann::json{{"node_visits", *nodeVisits},
                                                    {"triangle_tests", orNull(triangleTests)},
                                                    {"node_visits_per_ray", raysTraced && *raysTraced ? double(*nodeVisits) / double(*raysTraced) : 0.0}}
                                   : nlohmann::json(nullptr)},
          {"samples_per_pixel", samplesPerPixel},
          {"memory_bytes", memoryBytes},
          {"setup_ms", setupMs},
          {"error", error ? penumbra::toJson(*error) : nlohmann::json(nullptr)}};
}

}  // namespace penumbra
