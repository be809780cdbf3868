// The sweep engine of `penumbra bench` and `penumbra tune`: every configuration gets a warm-up,
// repeated frames (median reported with min/max) and its error against the Embree reference of its
// scene and light; rows carry machine, driver and device. The parameters a sweep can vary are the
// declared options that say so (core/options.h: SweepAxis), and --tracer.
#pragma once
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/run_config.h"
#include "core/options.h"

namespace penumbra {

// A parameter axis: the bench option naming its list, the run option it sets, the methods it changes
// (other methods are not re-run for each value), and the short name used in chart labels.
struct AxisDef {
  std::string names;   // CLI11 names of the bench option
  std::string option;  // the run option (addRunOptions) it sets
  SweepAxis axis;      // short name, methods, when it applies
  std::string help;
};

// Every sweepable parameter: --tracer first (the line-space axes depend on it), then the declared
// options that can be swept, in their order.
const std::vector<AxisDef>& sweepAxes();

// Run options as the command line spells them, e.g. {"--shadow-map-res", "1024"}.
using RunOptions = std::vector<std::pair<std::string, std::string>>;

// The shortest text that reads back as the same float: 0.1, not 0.100000001.
std::string shortNumber(float value);
// A parameter as chart labels show it ("res=1024"; the bare value for axes without a short name).
std::string paramText(const std::string& option, const std::string& value);
// The value `params` give `option`, or nullptr.
const std::string* findParam(const RunOptions& params, const std::string& option);

// Applies options through the very parser `render` and `compare` use (addRunOptions), so every run
// option, including ones later methods add, can be swept and is checked the same way. InputError
// when an option does not exist in this build or a value is refused.
void applyRunOptions(RunConfig& config, const RunOptions& options);

// One configuration of a sweep: a method and the run options that set its parameters.
struct SweepConfig {
  std::string method;
  RunOptions params;
  std::string label;  // the method and the parameters that vary in the sweep, for charts and tables
};

struct Sweep {
  RunConfig base;  // shared by every run: resolution, camera, light, warm-up, repeat, validation, ...
  std::vector<std::string> scenes;
  std::vector<float> lightSizes{0.0f};
  // The configurations to run at one light size (parameters that only matter for area lights drop out at 0).
  std::function<std::vector<SweepConfig>(float lightSize)> configsFor;
  std::uint32_t referenceSpp = 0;  // 0: the largest --spp among the configurations, else base.spp
  std::string imagesDir;           // set: images of ref and each method's first configuration per group
  bool progress = true;            // a progress bar on stderr when it is a terminal
  // Measure round-robin (one frame of each configuration per round, all renderers alive) rather than
  // each configuration's frames back to back: on a shared machine, load then falls on all alike.
  bool interleave = false;
  // Temporal stability: after its measured frames, each configuration (and the reference) renders
  // this many more frames with the light circling by temporalStepDeg per frame; rows get the mean
  // frame-to-frame change of the visibility (temporal_change) and the reference's (ref_temporal_change),
  // and shadow terms the mean rmse over the frames after the light began to move against the
  // reference's same frame (moving_rmse).
  std::uint32_t temporalFrames = 0;
  float temporalStepDeg = 0.25f;
  // Scale-out: this run measures configurations shardIndex, shardIndex + shardCount, ... of the
  // sweep's (groups in order, configurations in order), each with its group's reference; rows
  // carry their group and configuration index, so that mergeBench puts shards back in order.
  std::uint32_t shardIndex = 0, shardCount = 1;
  // Resuming (bench --resume): groups (scene x light size) that skipGroup names are not run;
  // onGroup receives each group's rows as soon as they are final, to keep them.
  std::function<bool(std::size_t group)> skipGroup;
  std::function<void(std::size_t group, const nlohmann::json& rows)> onGroup;
};

struct SweepResult {
  nlohmann::json rows = nlohmann::json::array();  // one per configuration and one per reference
  std::string machine, device, driver;
};

// Checks every scene, light size and parameter value first (InputError before any output), then
// renders. Vulkan validation messages (with base.validate) make it throw.
SweepResult runSweep(const Sweep& sweep);

// Combines the output folders of a split sweep (bench --shard K/N, one folder per shard) into the
// bench.json of one unsplit run: its rows in its order (each group's reference once), and copies
// the shards' frames/ into outDir. InputError unless the folders are the N shards of one sweep.
nlohmann::json mergeBench(const std::vector<std::string>& dirs, const std::string& outDir);

// CPU model, hardware threads, memory and architecture, e.g. "AMD EPYC 7B13, 2 threads, 24 GiB, x86_64".
std::string machineDescription();

// One CSV row per JSON row (header first; fields quoted where needed).
void writeBenchCsv(const std::string& path, const nlohmann::json& rows);

// Markdown tables of a bench (bench.json's object), readable where no Python is: every configuration
// (time, spread, PIP %, rays, rays/s of the trace pass, error, memory), then Lauterbach et al. 2009's
// Fig. 8 shape per scene, resolution, light and tracer: sm, srt and frt with srt's model bound, the sm
// frame plus srt's traced share (PIP %) of frt's trace pass.
void writeBenchTables(const std::string& path, const nlohmann::json& bench);

// Prints label, time, PIP and error per row.
void printSweepSummary(const nlohmann::json& rows, std::ostream& out);

}  // namespace penumbra
