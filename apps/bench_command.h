// `penumbra bench`: sweeps methods x parameters x scenes x light sizes. Every configuration gets a
// warm-up, repeated frames (median reported with min/max) and its error against the Embree
// reference of its scene and light; bench.csv and bench.json carry machine, driver and device on
// every row, and report.py turns bench.json into charts and report.html. The engine is
// apps/sweep.h, which `tune` runs on a short list of candidates.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/run_config.h"
#include "apps/sweep.h"

namespace penumbra {

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
  std::uint32_t temporalFrames_ = 3;  // temporal stability frames per configuration
  bool noReport_ = false, noImages_ = false;
  std::string shard_;                // "K/N": this run's share of the configurations
  std::vector<std::string> merge_;  // the shards' output folders to combine, instead of a sweep
  bool resume_ = false;             // keep the groups whose rows out/rows/ already holds
  nlohmann::json identity() const;  // the options given (but where to write): what makes rows reusable
  // bench.json, bench.csv, the summary and the report, in base_.outDir.
  void write(const nlohmann::json& bench) const;
};

}  // namespace penumbra
