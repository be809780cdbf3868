// Writes what a run produced: per-method images, visibility buffers, stats, heatmaps, metrics.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "hybrid/renderer.h"

namespace penumbra {

// dir/<method>.png, dir/<method>.visibility.exr (lossless float), dir/<method>.visibility.png
// (16-bit grey, for viewers), dir/<method>.stats.json (stats + `context`) and, for methods that
// classify, dir/<method>.pip.png (traced pixels in red); a frame of several lights also
// dir/lights/<method>.<i>.visibility.png (and .pip.png) for each light i whose buffers it kept.
void writeFrame(const std::string& dir, const Frame& frame, const nlohmann::json& context);

// dir/<method>.heatmap.png: |frame - reference| over covered pixels, white at fullScale; a frame of
// several lights also dir/lights/<method>.<i>.heatmap.png against the reference's light i.
void writeHeatmap(const std::string& dir, const Frame& frame, const Frame& reference, float fullScale);

void writeJson(const std::string& path, const nlohmann::json& value);

// A run's output folder, written all at once: files go to a staging folder beside it
// (DIR.partial-PID) and move into DIR, metrics.json last, when commit() runs. A run that fails
// leaves DIR as it was; one killed meanwhile leaves the staging folder, never a DIR whose images
// look complete beside no metrics.
class StagedOutput {
 public:
  explicit StagedOutput(const std::string& dir);
  ~StagedOutput();  // removes the staging folder unless committed
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  const std::string& path() const { return staging_; }  // where the run writes
  void commit();

 private:
  std::string dir_, staging_;
  bool committed_ = false;
};

}  // namespace penumbra
