// `penumbra bench`: sweeps methods x parameters x scenes x light sizes. Every configuration gets a
// warm-up, repeated frames (median reported with min/max) and its error against the Embree
// reference of its scene and light; bench.csv and bench.json carry machine, driver and device on
// every row, and report.py turns bench.json into charts and report.html. `tune` runs the same
// engine on a short list of candidates.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "apps/run_config.h"

namespace penumbra {

// Run options as the command line spells them, e.g. {"--shadow-map-res", "1024"}.
using RunOptions = std::vector<std::pair<std::string, std::string>>;

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
};

struct SweepResult {
  nlohmann::json rows = nlohmann::json::array();  // one per configuration and one per reference
  std::string machine, device, driver;
};

// Checks every scene, light size and parameter value first (InputError before any output), then
// renders. Vulkan validation messages (with base.validate) make it throw.
SweepResult runSweep(const Sweep& sweep);

// CPU model, hardware threads, memory and architecture, e.g. "AMD EPYC 7B13, 2 threads, 24 GiB, x86_64".
std::string machineDescription();

// One CSV row per JSON row (header first; fields quoted where needed).
void writeBenchCsv(const std::string& path, const nlohmann::json& rows);

// Prints label, time, PIP and error per row.
void printSweepSummary(const nlohmann::json& rows, std::ostream& out);

class BenchCommand {
 public:
  explicit BenchCommand(CLI::App& app);  // registers the `bench` subcommand and its options
  bool parsed() const { return command_->parsed(); }
  int run();

 private:
  CLI::App* command_;
  RunConfig base_;
  std::string methods_ = "sm,pcf,srt,frt", scenes_ = "builtin:courtyard", lightSizes_ = "0";
  std::vector<std::string> axisValues_;  // per parameter axis (see bench_command.cpp), comma-separated
  std::uint32_t referenceSpp_ = 0;
  bool noReport_ = false, noImages_ = false;
};

}  // namespace penumbra
