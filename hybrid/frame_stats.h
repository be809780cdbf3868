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

namespace penumbra {

struct FrameStats {
  std::string method;
  std::optional<std::string> tracer;    // which ray tracer answered rays, if any
  std::optional<double> pipFraction;    // fraction of covered pixels classified for tracing
  std::optional<std::uint64_t> raysTraced;
  std::uint32_t samplesPerPixel = 1;    // light samples per traced pixel (1 for point-like lights)
  double totalMs = 0.0;                 // wall time of the frame, setup excluded
  std::vector<std::pair<std::string, double>> passMs;  // per pass: GPU timestamps, CPU wall time
  std::map<std::string, std::uint64_t> memoryBytes;    // per structure
  std::map<std::string, double> setupMs;               // one-time work (e.g. acceleration build)
  std::optional<ErrorMetrics> error;                   // vs the reference, when compared

  void addPass(const std::string& pass, double ms) { passMs.emplace_back(pass, ms); }
  nlohmann::json toJson() const;
};

nlohmann::json toJson(const ErrorMetrics& error);

}  // namespace penumbra
