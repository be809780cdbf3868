#include "hybrid/frame_stats.h"

namespace penumbra {

nlohmann::json toJson(const ErrorMetrics& e) {
  return {{"rmse", e.rmse}, {"mae", e.mae}, {"max", e.max}, {"wrong_pixel_fraction", e.wrongPixelFraction}, {"pixels", e.pixels}};
}

nlohmann::json FrameStats::toJson() const {
  auto orNull = [](const auto& optional) { return optional ? nlohmann::json(*optional) : nlohmann::json(nullptr); };
  nlohmann::json times = {{"total", totalMs}};
  for (const auto& [pass, ms] : passMs) times[pass] = times.value(pass, 0.0) + ms;
  return {{"method", method},
          {"tracer", orNull(tracer)},
          {"time_ms", times},
          {"pip_fraction", orNull(pipFraction)},
          {"rays_traced", orNull(raysTraced)},
          {"samples_per_pixel", samplesPerPixel},
          {"memory_bytes", memoryBytes},
          {"setup_ms", setupMs},
          {"error", error ? penumbra::toJson(*error) : nlohmann::json(nullptr)}};
}

}  // namespace penumbra
