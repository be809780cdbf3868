#include "apps/tune_command.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>
#include <tuple>

#include "apps/report.h"
#include "hybrid/frame_output.h"
#include "hybrid/indirect_pass.h"
#include "hybrid/method.h"

namespace penumbra {
namespace {

bool methodExists(const std::string& name) {
  const auto names = methodNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

bool optionAccepted(const RunConfig& base, const RunOptions& options) {
  RunConfig probe = base;
  try {
    applyRunOptions(probe, options);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

SweepConfig candidate(const std::string& method, RunOptions params) {
  std::string label = method;
  for (const auto& [option, value] : params) {
    label += " " + (option == "--shadow-map-res" ? "res=" + value : option == "--msm-maps" ? "K=" + value : value);
  }
  return {method, std::move(params), label};
}

// Work order for ties: what each method adds on top of the one before it.
int methodRank(const std::string& method) {
  static const char* const order[] = {"sm", "pcf", "pcss", "msm", "srt", "bitmask", "ls", "frt"};
  for (int i = 0; i < int(std::size(order)); ++i) {
    if (method == order[i]) return i;
  }
  return int(std::size(order));
}

// ref, and ao's and indirect's Embree references (rows with a negative configuration index).
bool isReference(const nlohmann::json& row) { return row["method"] == "ref" || row.value("config", 0L) < 0; }

std::string metricKey(const std::string& metric) {
  if (metric == "wrong") return "wrong_pixel_fraction";
  return metric;  // rmse, mae, max (checked by the option)
}

}  // namespace

std::vector<SweepConfig> tuneCandidates(const RunConfig& base, float lightSize) {
  std::vector<SweepConfig> c;
  const bool area = lightSize > 0.0f;
  for (const char* res : area ? std::vector<const char*>{"2048"} : std::vector<const char*>{"512", "1024", "2048", "4096"}) {
    c.push_back(candidate("sm", {{"--shadow-map-res", res}}));
  }
  for (const char* res : area ? std::vector<const char*>{"2048"} : std::vector<const char*>{"1024", "2048"}) {
    for (const char* kernel : {"3x3", "5x5"}) c.push_back(candidate("pcf", {{"--shadow-map-res", res}, {"--pcf-kernel", kernel}}));
  }
  if (area) {
    for (const char* res : {"1024", "2048"}) c.push_back(candidate("pcss", {{"--shadow-map-res", res}}));
    for (const char* maps : {"4", "16"}) c.push_back(candidate("msm", {{"--shadow-map-res", "2048"}, {"--msm-maps", maps}}));
  }
  for (const char* res : {"1024", "2048"}) c.push_back(candidate("srt", {{"--shadow-map-res", res}}));
  c.push_back(candidate("frt", {}));
  // Methods and tracers that later builds add join when this build has them.
  if (base.tracer != "ls" && optionAccepted(base, {{"--tracer", "ls"}})) {
    c.push_back(candidate("srt", {{"--shadow-map-res", "2048"}, {"--tracer", "ls"}}));
    c.push_back(candidate("frt", {{"--tracer", "ls"}}));
  }
  if (methodExists("ls")) c.push_back(candidate("ls", {}));
  if (area && methodExists("bitmask")) c.push_back(candidate("bitmask", {}));  // it samples an area light
  return c;
}

std::vector<SweepConfig> indirectTuneCandidates(const std::string& method) {
  std::vector<SweepConfig> c;
  for (const std::string& tracer : indirectTracers()) {
    if (tracer == "embree") continue;  // the reference
    if (tracer != "bvh-ls") {
      c.push_back(candidate(method, {{"--tracer", tracer}}));
      continue;
    }
    for (const char* depth : {"6", "9"}) c.push_back(candidate(method, {{"--tracer", tracer}, {"--bvh-ls-depth", depth}}));
    // Deeper line spaces at N = 6 exceed one storage buffer on lavapipe (128 MiB): N = 4 there.
    c.push_back(candidate(method, {{"--tracer", tracer}, {"--bvh-ls-depth", "12"}, {"--linespace-n", "4"}}));
  }
  return c;
}

nlohmann::json chooseCheapest(const nlohmann::json& rows, const std::string& key, double maxError) {
  std::vector<const nlohmann::json*> feasible;
  for (const nlohmann::json& r : rows) {
    if (isReference(r) || r["error"].is_null() || r["error"][key].is_null()) continue;
    if (r["error"][key].get<double>() <= maxError) feasible.push_back(&r);
  }
  if (feasible.empty()) return nullptr;
  const nlohmann::json* fastest = *std::min_element(feasible.begin(), feasible.end(), [](const nlohmann::json* a, const nlohmann::json* b) {
    return (*a)["time_ms"].get<double>() < (*b)["time_ms"].get<double>();
  });
  const double fastestMax = (*fastest)["time_max_ms"].get<double>();
  auto work = [](const nlohmann::json* r) {
    const auto& res = (*r)["params"];
    return std::tuple((*r)["rays_traced"].is_null() ? 0ull : (*r)["rays_traced"].get<unsigned long long>(),
                      methodRank((*r)["method"].get<std::string>()),
                      res.contains("shadow-map-res") ? std::stoul(res["shadow-map-res"].get<std::string>()) : 0ul,
                      (*r)["time_ms"].get<double>());
  };
  const nlohmann::json* chosen = fastest;
  for (const nlohmann::json* r : feasible) {
    if ((*r)["time_min_ms"].get<double>() <= fastestMax && work(r) < work(chosen)) chosen = r;
  }
  return *chosen;
}

TuneCommand::TuneCommand(CLI::App& app) {
  command_ = app.add_subcommand("tune",
                                "Name the cheapest method and parameters whose error vs the Embree reference stays within "
                                "--max-error, with the chart that justifies it (tune.png, report.html)");
  base_.outDir = "out/tune";
  base_.repeat = 3;
  addRunOptions(*command_, base_);
  command_->add_option("--max-error", maxError_, "Largest acceptable error against the reference (see --metric)")
      ->required()
      ->check(CLI::Range(0.0, 1.0));
  command_->add_option("--metric", metric_,
                       "Error measure: wrong (fraction of covered pixels with |error| > 0.5 hard / 0.05 soft), rmse, mae, "
                       "max (of the visibility)")
      ->capture_default_str()
      ->check(CLI::IsMember({"wrong", "rmse", "mae", "max"}));
  command_->add_option("--methods", methods_,
                       "Only consider these methods (comma-separated), e.g. sm,pcf,srt; default: every method this build has");
  command_->add_option("--reference-spp", base_.referenceSpp, "Light samples per pixel of the reference (default: --spp)");
  command_->add_flag("--no-report", noReport_, "Do not run report.py (tune.png and report.html)");
}

int TuneCommand::run() {
  std::vector<std::string> only;
  if (!methods_.empty()) {
    only = splitList(methods_);
    for (const std::string& m : only) makeMethod(m);  // unknown names fail here
  }
  // ao and indirect are tuned on their own (their error is of another term): their tracers.
  std::vector<std::string> indirect;
  for (const std::string& m : only) {
    if (methodTerm(m) != Term::Shadow) indirect.push_back(m);
  }
  if (!indirect.empty() && indirect.size() != only.size()) {
    throw InputError("--methods '" + methods_ + "': tune ao and indirect apart from the shadow methods");
  }
  auto candidatesFor = [base = base_, only, indirect, text = methods_](float lightSize) {
    std::vector<SweepConfig> all, kept;
    if (indirect.empty()) all = tuneCandidates(base, lightSize);
    for (const std::string& m : indirect) {
      for (SweepConfig& c : indirectTuneCandidates(m)) all.push_back(std::move(c));
    }
    for (SweepConfig& c : all) {
      if (only.empty() || std::find(only.begin(), only.end(), c.method) != only.end()) kept.push_back(std::move(c));
    }
    if (kept.empty()) {
      throw InputError("--methods '" + text + "' leaves tune no candidate for this light; it tunes sm, pcf, srt and frt, "
                       "pcss and msm for area lights, and ls where the build has it");
    }
    return kept;
  };
  Sweep sweep;
  sweep.base = base_;
  sweep.scenes = {base_.scene};
  sweep.lightSizes = {base_.lightSize};
  sweep.configsFor = candidatesFor;
  sweep.referenceSpp = base_.referenceSpp ? base_.referenceSpp : base_.settings.spp;
  sweep.interleave = true;  // the choice compares times: measure them under the same load
  const SweepResult result = runSweep(sweep);

  const std::string key = metricKey(metric_);
  const nlohmann::json chosen = chooseCheapest(result.rows, key, maxError_);
  std::ostringstream verdict;
  std::size_t within = 0, candidates = 0;
  for (const nlohmann::json& r : result.rows) {
    if (isReference(r)) continue;
    ++candidates;
    if (!r["error"].is_null() && r["error"][key].get<double>() <= maxError_) ++within;
  }
  if (chosen.is_null()) {
    verdict << "No candidate keeps " << key << " within " << maxError_ << " on " << base_.scene << "; see the chart.";
  } else {
    verdict << "Cheapest within " << key << " <= " << maxError_ << " on " << base_.scene << ": " << chosen["label"].get<std::string>()
            << " (" << chosen["time_ms"].get<double>() << " ms median, " << key << " " << chosen["error"][key].get<double>()
            << "); " << within << " of " << candidates
            << " candidates qualify. Times whose min-max ranges overlap the fastest qualifying one count as equal; among "
               "those the least work wins (fewest rays, simpler method, smaller shadow map).";
  }
  const nlohmann::json tune{{"scene", base_.scene},
                            {"metric", key},
                            {"max_error", maxError_},
                            {"chosen", chosen},
                            {"verdict", verdict.str()},
                            {"machine", result.machine},
                            {"device", result.device},
                            {"driver", result.driver},
                            {"rows", result.rows}};
  std::filesystem::create_directories(base_.outDir);
  writeJson(base_.outDir + "/tune.json", tune);
  writeBenchCsv(base_.outDir + "/tune.csv", result.rows);
  printSweepSummary(result.rows, std::cout);
  if (!noReport_) writeReport("tune", base_.outDir);
  std::cout << verdict.str() << "\n";
  if (chosen.is_null()) {
    std::cout << "wrote " << base_.outDir << "/\n";
    return 1;
  }
  std::cout << "use: --method " << chosen["method"].get<std::string>();
  for (const auto& [option, value] : chosen["params"].items()) std::cout << " --" << option << " " << value.get<std::string>();
  std::cout << "\nwrote " << base_.outDir << "/\n";
  return 0;
}

}  // namespace penumbra
