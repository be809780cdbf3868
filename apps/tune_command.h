// `penumbra tune --scene S --max-error E`: model no more than a scene needs. A short sweep of the
// methods and parameters this build has (shadow-map sizes, PCF kernels, srt, frt, and for area
// lights pcss and msm) measured against the Embree reference; names the cheapest configuration
// whose error stays within E, and writes the chart that justifies it (tune.png, report.html).
#pragma once
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "apps/bench_command.h"

namespace penumbra {

// The configurations tune measures for a light of this size (0 = point or directional light).
std::vector<SweepConfig> tuneCandidates(const RunConfig& base, float lightSize);
// ao or indirect (--methods ao / indirect): each of its tracers, bvh-ls at depths 6, 9 and 12.
std::vector<SweepConfig> indirectTuneCandidates(const std::string& method);

// Among rows (bench.json shape; the reference is skipped) whose error[metricKey] <= maxError: the
// fastest by median time, except that times whose min-max ranges overlap the fastest's are not a
// measured difference, and among those the least work wins: fewest rays, then the simpler method
// (sm, pcf, pcss, msm, srt, bitmask, ls, frt), then the smaller shadow map. Null when none qualifies.
nlohmann::json chooseCheapest(const nlohmann::json& rows, const std::string& metricKey, double maxError);

class TuneCommand {
 public:
  explicit TuneCommand(CLI::App& app);  // registers the `tune` subcommand and its options
  bool parsed() const { return command_->parsed(); }
  int run();

 private:
  CLI::App* command_;
  RunConfig base_;
  double maxError_ = 0.0;
  std::string metric_ = "wrong";
  std::string methods_;  // restricts the candidates to these methods; empty: all
  bool noReport_ = false;
};

}  // namespace penumbra
