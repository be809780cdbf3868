// Writes what a run produced: per-method images, visibility buffers, stats, heatmaps, metrics.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "hybrid/renderer.h"

namespace penumbra {

// dir/<method>.png, dir/<method>.visibility.exr (lossless float), dir/<method>.visibility.png
// (16-bit grey, for viewers), dir/<method>.stats.json (stats + `context`) and, for methods that
// classify, dir/<method>.pip.png (traced pixels in red).
void writeFrame(const std::string& dir, const Frame& frame, const nlohmann::json& context);

// dir/<method>.heatmap.png: |frame - reference| over covered pixels, white at fullScale.
void writeHeatmap(const std::string& dir, const Frame& frame, const Frame& reference, float fullScale);

void writeJson(const std::string& path, const nlohmann::json& value);

}  // namespace penumbra
