// Scripted runs of the demo, for tests and recordings: a fixed number of frames with fixed steps
// per frame (camera orbit, light circle, animation time), a screenshot of the last frame, one CSV
// row per frame. Fixed steps make a scripted run the same on any machine, however fast.
#pragma once
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "apps/demo/overlay.h"
#include "hybrid/frame_stats.h"

namespace penumbra::demo {

inline constexpr float kOrbitStepDeg = 1.5f;         // --orbit: camera yaw per frame
inline constexpr float kLightStepDeg = 1.0f;         // --light-path circle: light azimuth per frame
inline constexpr double kScriptedFrameSeconds = 1.0 / 30.0;  // animation time per scripted frame

struct ScriptOptions {
  std::uint32_t frames = 0;  // 0: interactive
  bool orbit = false;
  std::string lightPath = "none";
  std::string screenshot, statsCsv;
  bool temporalReference = false;
  std::string overlay = "none";
  std::size_t selectLight = 0;  // the light selected at start
  bool hideUi = false;

  bool scripted() const { return frames > 0; }
};

void addScriptOptions(CLI::App& app, ScriptOptions& options);

// Resident set size of this process from /proc/self/statm, in bytes.
std::uint64_t residentBytes();

struct FrameRecord {
  std::uint32_t frame = 0;
  double timeS = 0.0;  // animation time
  const FrameStats* stats = nullptr;
  std::uint64_t rssBytes = 0;
  std::optional<double> temporalChange, referenceTemporalChange;
};

// --stats-csv: frame, time_s, method, tracer, total_ms, passes ("name=ms;..."), pip_fraction, rays,
// memory_bytes (sum of the stats' structures), rss_bytes, temporal_change (mean |Δvisibility| vs the
// previous frame), ref_temporal_change (with --temporal-reference), refit_ms, sah_growth (the refit
// tree's SAH over its SAH when last built, each relative to its root box, so a turn that widens the
// root more than the inner boxes gives < 1; above the limit it was rebuilt), rebuilt. Empty cells where a value does not apply.
class StatsCsv {
 public:
  explicit StatsCsv(const std::string& path);  // InputError when it cannot be written
  void write(const FrameRecord& record);

 private:
  std::string path_;
  std::ofstream out_;
};

}  // namespace penumbra::demo
